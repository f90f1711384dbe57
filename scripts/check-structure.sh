#!/usr/bin/env bash
# The tree's shape, so that later work cannot undo it (issue 28): no source file over 1,000
# lines and no function over 80 lines in src/, cli/, bench/, viewer/ and web/. An exception, if
# one is ever granted, is listed below with its size: it may shrink, never grow, and leaves the
# list (the check says so) once it is within the limit. None today. A function is counted from its opening brace
# to its closing one, both in column 0 (the house style, .clang-format).
#   bash scripts/check-structure.sh          # the check
#   bash scripts/check-structure.sh --list   # what is over the limits now
set -euo pipefail
cd "$(dirname "$0")/.."
file_limit=1000
function_limit=80

# path max-lines, and path:function max-lines: what may be over the limits (nothing today).
exceptions="
"

measure() { # prints "path lines" for every file, "path:function lines" for every function
  local f
  for f in $(git ls-files -co --exclude-standard 'src/*.c' 'src/*.h' 'cli/*.c' 'cli/*.h' 'bench/*.c' 'bench/*.h' \
    'viewer/*.c' 'viewer/*.h' 'viewer/*.cpp' 'web/*.c'); do
    echo "$f $(wc -l <"$f")"
    # A function's name: the last word before the first "(" of the declaration that starts in
    # column 0 above its brace; a closing "} name;" or "};" ends a struct, enum or array.
    awk -v file="$f" '
      /^[A-Za-z_]/ { declaration = $0 }
      /^\{/ { start = NR; name = declaration; sub(/\(.*/, "", name); n = split(name, w, /[ *]+/); name = w[n] }
      /^\}/ && start { if ($0 ~ /^\}[ \t]*$/) print file ":" name " " NR - start + 1; start = 0 }' "$f"
  done
}
over() { # the measured items beyond their limit
  measure | awk -v fl="$file_limit" -v gl="$function_limit" '
    ($1 ~ /:/ && $2 > gl) || ($1 !~ /:/ && $2 > fl) { print }'
}
if [ "${1:-}" = --list ]; then
  over | sort -k2 -rn
  exit 0
fi

declare -A allowed=()
while read -r item size; do
  [ -n "$item" ] && allowed[$item]=$size
done <<<"$exceptions"
failures=0
fail() { echo "check-structure: $*" >&2; failures=$((failures + 1)); }
declare -A seen=()
while read -r item size; do
  seen[$item]=1
  limit=$function_limit kind=function
  [[ $item == *:* ]] || { limit=$file_limit kind=file; }
  if [ -z "${allowed[$item]+x}" ]; then
    fail "$item: $size lines, over the $kind limit of $limit (split it)"
  elif [ "$size" -gt "${allowed[$item]}" ]; then
    fail "$item: $size lines, more than the ${allowed[$item]} it was allowed (it may only shrink)"
  fi
done < <(over)
for item in "${!allowed[@]}"; do
  [ -n "${seen[$item]+x}" ] ||
    fail "$item is within the limits now (or gone): take it off the list in scripts/check-structure.sh"
done
[ "$failures" = 0 ] || exit 1
echo "check-structure: no file over $file_limit lines and no function over $function_limit lines (${#allowed[@]} exceptions listed)"
