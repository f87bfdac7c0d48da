#!/bin/bash
# usermb-list.sh DIR: the meshes of a user modelbase (mk/usermb.mk, docs/decisions/user-modelbase.md),
# read once per parse of `make user-modelbase`. Prints one word per mesh, sorted by name (C
# locale): NAME:FILE:CLASS, FILE = DIR/NAME.<ext> (.obj, .ply or .stl, any case), CLASS = "-"
# when the mesh has none. The class: "<class>__<rest>" in the name gives <class>; a row
# "NAME,CLASS" of DIR/classes.csv (header "name,class") overrides it.
# On a problem it prints "ERROR <message>" instead (make turns it into $(error ...)): DIR
# missing or without a mesh, a name that is not a word of [A-Za-z0-9_.-], two meshes with one
# name, a malformed classes.csv or class.
set -u
export LC_ALL=C
dir=${1:-}
fail() { echo "ERROR $*"; exit 0; }
[ -n "$dir" ] || fail "give MESHES=<directory of .obj/.ply/.stl vehicle meshes>"
dir=${dir%/}
[ -d "$dir" ] || fail "MESHES=$1 is not a directory"
case $dir in *[!A-Za-z0-9_./-]*) fail "MESHES=$1: the directory's path must be made of [A-Za-z0-9_./-] (make cannot name other files)" ;; esac

declare -A file_of csv_class
names=()
while IFS= read -r -d '' path; do
  base=${path##*/}
  name=${base%.*}
  case $base in
    *[!A-Za-z0-9_.-]* | .* ) fail "mesh '$path': its name must be a word of [A-Za-z0-9_.-] not starting with '.' (rename the file)" ;;
  esac
  [ -n "$name" ] || fail "mesh '$path' has no name before its extension"
  [ -z "${file_of[$name]:-}" ] || fail "meshes '${file_of[$name]}' and '$path' give the same entry name '$name'"
  file_of[$name]=$path
  names+=("$name")
done < <(find "$dir" -maxdepth 1 \( -type f -o -type l \) \( -iname '*.obj' -o -iname '*.ply' -o -iname '*.stl' \) -print0)
[ ${#names[@]} -gt 0 ] || fail "MESHES=$1 holds no mesh (.obj, .ply or .stl)"

valid_class() { [[ $1 =~ ^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$ ]]; }
csv=$dir/classes.csv
if [ -f "$csv" ]; then
  line_no=0
  while IFS= read -r line || [ -n "$line" ]; do
    line_no=$((line_no + 1))
    line=${line%$'\r'}
    if [ $line_no = 1 ]; then
      [ "$line" = "name,class" ] || fail "$csv: the first line must be 'name,class', not '$line'"
      continue
    fi
    [ -n "$line" ] || continue
    IFS=, read -r n c extra <<<"$line"
    [ -n "$n" ] && [ -z "${extra:-}" ] && [[ $line == *,* ]] || fail "$csv:$line_no: expected 'name,class', got '$line'"
    valid_class "$c" || fail "$csv:$line_no: class '$c' must be one word of [A-Za-z0-9_.-] starting with a letter or digit (at most 64 characters)"
    csv_class[$n]=$c
  done <"$csv"
fi

out=()
while IFS= read -r name; do
  cls=-
  if [[ $name == ?*__* ]]; then
    cls=${name%%__*}
    valid_class "$cls" || fail "mesh '${file_of[$name]}': class '$cls' (before '__') must be one word of [A-Za-z0-9_.-] starting with a letter or digit (at most 64 characters)"
  fi
  [ -z "${csv_class[$name]:-}" ] || cls=${csv_class[$name]}
  out+=("$name:${file_of[$name]}:$cls")
done < <(printf '%s\n' "${names[@]}" | sort)
echo "${out[@]}"
