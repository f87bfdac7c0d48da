#!/usr/bin/env bash
# CLI contract of one canopy tool binary ($1): --help and --version exit 0 with output,
# no arguments (stdin = /dev/null) exits 2, an unknown option exits 2, a config file with an
# unknown key exits 2 naming the file and the key, a directory as the config file exits 2 saying
# so; usage errors print "<tool>: error:" on stderr.
set -u
bin=$1
name=$(basename "$bin")
fail() { echo "FAIL [$name]: $*" >&2; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

"$bin" --help >"$tmp/help" 2>&1 </dev/null; rc=$?
[ $rc -eq 0 ] || fail "--help exited $rc"
grep -q -- "--help" "$tmp/help" || fail "--help output does not list --help"
"$bin" --version >"$tmp/version" 2>&1 </dev/null; rc=$?
[ $rc -eq 0 ] || fail "--version exited $rc"
grep -q "$name" "$tmp/version" || fail "--version does not name the tool"
"$bin" </dev/null >"$tmp/out" 2>"$tmp/err"; rc=$?
[ $rc -eq 2 ] || fail "no arguments exited $rc, want 2"
"$bin" --no-such-option-xyz </dev/null >"$tmp/out" 2>"$tmp/err"; rc=$?
[ $rc -eq 2 ] || fail "unknown option exited $rc, want 2"
grep -q "$name: error:" "$tmp/err" || fail "usage error message lacks '$name: error:'"
printf 'no_such_key_xyz = 1\n' >"$tmp/bad.ini"
"$bin" --config "$tmp/bad.ini" </dev/null >"$tmp/out" 2>"$tmp/err"; rc=$?
[ $rc -eq 2 ] || fail "unknown config key exited $rc, want 2"
if grep -q -- "--config" "$tmp/help"; then  # (stagerun, no tool of the wrapper, has none)
  grep -qF "$name: error: --config $tmp/bad.ini: unknown key 'no_such_key_xyz'" "$tmp/err" \
    || fail "unknown config key: the message names not the file and the key: $(head -1 "$tmp/err")"
  "$bin" --config "$tmp" </dev/null >"$tmp/out" 2>"$tmp/err"; rc=$?
  [ $rc -eq 2 ] || fail "a directory as --config exited $rc, want 2"
  grep -qF "$name: error: --config $tmp: is a directory" "$tmp/err" \
    || fail "a directory as --config: the message does not say so: $(head -1 "$tmp/err")"
fi
echo "ok [$name]"
