# Tests of the renderer and the viewer (viewer/): the pictures of femto run --gif/--png decode
# to what was asked, and femto view plays a script under a virtual display. Included by
# cli_tests.cmake. Where the viewer's packages (or xvfb) are missing the tests are reported as
# skipped, with the reason (femto_missing_tool_test), and fail under CI=true.
set(FEMTO_VIEW_WORK ${CMAKE_CURRENT_BINARY_DIR}/viewer_work)
set(FEMTO_VIEW_DATA ${PROJECT_SOURCE_DIR}/viewer/tests)
file(MAKE_DIRECTORY ${FEMTO_VIEW_WORK})

# Options are checked whether or not the renderer was built.
femto_cli_test(gif_size_too_small ARGS "run|--gif|x.gif|--size|8x8" CODE 2
  REGEX "--size: expected WxH with sides in \\[16, 8192\\], got '8x8'")
femto_cli_test(gif_size_without_output ARGS "run|--size|320x240" CODE 2
  REGEX "--size, --fps, --camera-\\* and --draw need --gif FILE or --png DIR")
femto_cli_test(gif_fps_too_high ARGS "run|--gif|x.gif|--fps|60" CODE 2 REGEX "at most 50")
femto_cli_test(gif_bad_draw ARGS "run|--gif|x.gif|--draw|surfaces,walls" CODE 2
  REGEX "--draw: unknown 'walls'")
femto_cli_test(gif_bad_target ARGS "run|--png|d|--camera-target|1,2" CODE 2
  REGEX "--camera-target: expected X,Y,Z")

if(NOT TARGET femto_viewer)
  femto_missing_tool_test(viewer_skipped "femto was built without the renderer (apt-get install libepoxy-dev libegl-dev libgl-dev libgif-dev libspng-dev)")
  femto_cli_test(gif_without_renderer ARGS "run|--frames|1|--gif|${FEMTO_VIEW_WORK}/x.gif" CODE 1
    REGEX "--gif needs femto's renderer.*apt-get install" REJECT "note: builtin:house")
  femto_cli_test(view_without_renderer ARGS "view" CODE 1 REGEX "femto view needs.*apt-get install")
  return()
endif()

# Collider batches in the draw list: grey, no body numbers, planes after the first as quads.
add_test(NAME viewer_draw_list_colliders COMMAND femto_draw_list_test)

# 20 frames of 0.03 s, pictures at 0, 1/30, ..., 0.6 s: 19. The house falls from rest 1 m onto
# the floor in about 0.45 s: its pixels move down over the first 12 pictures.
femto_cli_test(gif_run ARGS "run|--frames|20|--quiet|--size|320x240|--gif|${FEMTO_VIEW_WORK}/house.gif"
  CODE 0 REGEX "gif +.*house.gif \\(19 pictures, 320x240, 30 a second\\)"
  FILES "${FEMTO_VIEW_WORK}/house.gif")
set_tests_properties(cli_gif_run PROPERTIES FIXTURES_SETUP viewer_gif)
add_test(NAME viewer_gif_frames COMMAND femto_check_images gif ${FEMTO_VIEW_WORK}/house.gif 19 12)
set_tests_properties(viewer_gif_frames PROPERTIES FIXTURES_REQUIRED viewer_gif)

# 10 frames (0.3 s) at 10 pictures a second: 0, 0.1, 0.2, 0.3 s.
femto_cli_test(png_run ARGS "run|--frames|10|--quiet|--size|160x120|--fps|10|--draw|all|--png|${FEMTO_VIEW_WORK}/png"
  CODE 0 CLEAN "${FEMTO_VIEW_WORK}/png" FILES "${FEMTO_VIEW_WORK}/png/frame_0003.png")
set_tests_properties(cli_png_run PROPERTIES FIXTURES_SETUP viewer_png)
add_test(NAME viewer_png_frames COMMAND femto_check_images png ${FEMTO_VIEW_WORK}/png 4 160x120)
set_tests_properties(viewer_png_frames PROPERTIES FIXTURES_REQUIRED viewer_png)
# A shorter run into the same folder removes the earlier run's pictures (only frame_NNNN.png).
femto_cli_test(png_rerun ARGS "run|--frames|1|--quiet|--size|160x120|--fps|10|--png|${FEMTO_VIEW_WORK}/png"
  CODE 0 REGEX "removed 4 frame_NNNN.png of an earlier run" FILES "${FEMTO_VIEW_WORK}/png/frame_0000.png"
  NO_FILES "${FEMTO_VIEW_WORK}/png/frame_0001.png")
set_tests_properties(cli_png_rerun PROPERTIES FIXTURES_REQUIRED viewer_png DEPENDS viewer_png_frames)

femto_cli_test(gif_unwritable ARGS "run|--frames|1|--gif|${FEMTO_VIEW_WORK}/no/such/dir/x.gif"
  CODE 1 REGEX "no/such/dir/x.gif: cannot create")

# Under the sanitizers, Mesa's GL driver leaves two 56-byte blocks behind at exit, from a module
# it has already unloaded, which LeakSanitizer can neither name nor suppress: the tests that
# draw run there without leak detection (the other AddressSanitizer checks stay on; the script,
# option and no-display tests, which draw nothing, keep it).
if(FEMTO_SANITIZE)
  set_tests_properties(cli_gif_run cli_png_run cli_png_rerun cli_gif_unwritable
    PROPERTIES ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0")
endif()

if(NOT TARGET femto_view)
  femto_missing_tool_test(viewer_window_skipped "femto view was not built (apt-get install libglfw3-dev libimgui-dev g++)")
  femto_cli_test(view_without_window ARGS "view" CODE 1 REGEX "femto view needs.*apt-get install")
  return()
endif()

femto_cli_test(view_help ARGS "view|--help" CODE 0 REGEX "usage: femto view.*--script FILE")
femto_cli_test(view_script_without_frames ARGS "view|--script|s.txt" CODE 2
  REGEX "--script needs --frames")
femto_cli_test(view_gif_option ARGS "view|--gif|x.gif" CODE 2 REGEX "an option of femto run")

# Located script errors and a missing display need no window.
femto_cli_test(view_bad_script ARGS "view|--script|${FEMTO_VIEW_DATA}/bad_script.txt|--frames|5"
  CODE 1 REGEX "bad_script.txt:3: expected 'to' between the drag's two points")
femto_cli_test(view_nul_script ARGS "view|--script|${FEMTO_VIEW_DATA}/nul_script.txt|--frames|5"
  CODE 1 REGEX "nul_script.txt:2:9: a NUL byte: expected text")
femto_cli_test(view_huge_substeps ARGS "view|--script|${FEMTO_VIEW_DATA}/huge_substeps_script.txt|--frames|5"
  CODE 1 REGEX "huge_substeps_script.txt:1: expected a whole number of substeps in \\[1, 1000\\]")
femto_cli_test(view_missing_script ARGS "view|--script|${FEMTO_VIEW_WORK}/none.txt|--frames|5"
  CODE 1 REGEX "none.txt: cannot open")
add_test(NAME cli_view_no_display COMMAND ${CMAKE_COMMAND} -E env --unset=DISPLAY
  --unset=WAYLAND_DISPLAY $<TARGET_FILE:femto_cli> view --frames 1)
set_tests_properties(cli_view_no_display PROPERTIES LABELS cli PASS_REGULAR_EXPRESSION "no display \\(DISPLAY is not set\\)")

add_test(NAME viewer_window COMMAND ${FEMTO_VIEW_DATA}/view_test.sh $<TARGET_FILE:femto_cli>
  $<TARGET_FILE:femto_check_images> ${FEMTO_VIEW_DATA} ${FEMTO_VIEW_WORK}/window)
set_tests_properties(viewer_window PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 120 LABELS viewer)
if(FEMTO_SANITIZE)
  set_tests_properties(viewer_window PROPERTIES ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0;FEMTO_VIEW_TIMING=0")
endif()
