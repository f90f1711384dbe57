#!/bin/sh
# mask_tool.sh TOOL COMMAND [ARG...]: runs COMMAND with TOOL hidden from PATH (PATH becomes one
# folder of links to every other program on it), as on a machine without that tool. The tests of
# the skip rules use it: under CI=true a missing tool must fail the check that needed it.
set -eu
tool=$1
shift
masked=$(mktemp -d "${TMPDIR:-/tmp}/femto-masked-XXXXXX")
trap 'rm -rf "$masked"' EXIT
IFS=:
for dir in $PATH; do
  [ -d "$dir" ] || continue
  for program in "$dir"/*; do
    name=${program##*/}
    [ "$name" = "$tool" ] && continue
    [ -e "$masked/$name" ] || ln -s "$program" "$masked/$name" 2>/dev/null || true
  done
done
unset IFS
PATH=$masked "$@"
