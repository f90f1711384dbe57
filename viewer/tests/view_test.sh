#!/bin/sh
# The viewer under a virtual display: femto view plays a script with a drag, a jump and a slider,
# the same script without the drag, and one with every key, slider and view and the panel on; femto_check_images checks the screenshots and the
# report (docs/viewer.md, "Tests"). Without xvfb-run: exit 77 (CTest: skipped), a failure under CI=true.
#   view_test.sh FEMTO CHECK_IMAGES SCRIPTS_DIR WORK_DIR
set -eu
femto=$1 check=$2 scripts=$3 work=$4
if ! command -v xvfb-run >/dev/null 2>&1; then
  exec sh "$(dirname "$0")/../../tests/missing_tool.sh" "xvfb-run is not installed (apt-get install xvfb): femto view is not tested"
fi
mkdir -p "$work"
rm -f "$work"/drag.png "$work"/drag.txt "$work"/no_drag.png "$work"/no_drag.txt
# Each run plays 100 frames of exactly 1/60 s with the built-in house in a 640x480 window.
for run in drag no_drag; do
  xvfb-run -a -s "-screen 0 1024x768x24" "$femto" view --size 640x480 --no-ui \
    --script "$scripts/$run.txt" --frames 100 --screenshot "$work/$run.png" \
    --report "$work/$run.report"
done
# Every key, slider, view and a scene change with the panel on: runs to the end and saves.
rm -f "$work/keys.png"
xvfb-run -a -s "-screen 0 1024x768x24" "$femto" view --size 800x600 \
  --script "$scripts/keys.txt" --frames 60 --screenshot "$work/keys.png"
test -s "$work/keys.png"
cat "$work/drag.report"
"$check" view "$work/drag.png" "$work/drag.report" "$work/no_drag.png"
