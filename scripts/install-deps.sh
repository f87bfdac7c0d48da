#!/usr/bin/env bash
# Installs the Debian 12 packages canopy needs, only those missing (fast when all are present).
# clang and libclang-rt-14-dev (libFuzzer, sanitizer runtimes) build fuzz/; clang-format checks
# the style (scripts/check-format.sh).
# Runs apt-get as root, or through sudo.
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  libeigen3-dev libcgal-dev libpcl-dev libvtk9-dev libspectra-dev
  nlohmann-json3-dev libcli11-dev catch2 libpng-dev libssl-dev
  povray time xvfb xauth jq
  # bwrap: rangetrace runs POV-Ray in a bubblewrap jail (docs/decisions/sandbox.md).
  bubblewrap
  clang libclang-rt-14-dev clang-format
  # Slurm and munge: for LAUNCH=slurm and its test (tests/pipeline/slurm.sh), which starts
  # its own single-node cluster in a temp dir; nothing is configured system-wide.
  slurmctld slurmd slurm-client munge
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "install-deps: installing ${missing[*]}" >&2
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: error: need root or sudo to install ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
# Another apt (a boot-time upgrade, a second test run) may hold dpkg's lock: wait for it
# rather than fail.
lock=(-o DPkg::Lock::Timeout=1200)
$sudo apt-get "${lock[@]}" update -qq
$sudo apt-get "${lock[@]}" install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
