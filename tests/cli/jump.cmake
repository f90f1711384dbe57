# The seeds' space-bar jump (femto run --impulse-at): the house, settled on the floor after
# 10 s, must leave it. Runs FEMTO three times: 334 frames (10 s, no jump) for the resting centre
# of mass, then 341 frames (the peak, 0.21 s after the jump) with the jump and with a custom
# one-off impulse of 0.2 m/s (--impulse-speed), and checks
#   seeds' jump:  the centre of mass rises 0.15 to 0.25 m (free flight at 2 m/s: v^2 / 2g =
#                 0.204 m, less what the seeds' damping takes) and the lowest vertex is off the
#                 floor (y > -2.99);
#   0.2 m/s once: a rise under 0.06 m (v^2 / 2g = 2 mm plus the elastic rebound), on the floor.
#
#   cmake -DFEMTO=path/to/femto -P jump.cmake
cmake_minimum_required(VERSION 3.22)

# "-0.830344" -> -830344 (micrometres); CMake has integer arithmetic only.
function(to_micro text out)
  if(NOT text MATCHES "^(-?)([0-9]+)(\\.([0-9]*))?$")
    message(FATAL_ERROR "not a plain decimal: '${text}'")
  endif()
  set(sign "${CMAKE_MATCH_1}")
  set(whole "${CMAKE_MATCH_2}")
  string(SUBSTRING "${CMAKE_MATCH_4}000000" 0 6 fraction)
  math(EXPR value "${whole} * 1000000 + 1${fraction} - 1000000")
  set(${out} "${sign}${value}" PARENT_SCOPE)
endfunction()

# Run femto run --quiet with ARGN; set COM and LOWEST (micrometres) in the caller.
function(run_house)
  execute_process(COMMAND ${FEMTO} run --quiet ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  if(NOT code EQUAL 0 OR NOT out MATCHES "lowest vertex y +([-0-9.]+) m.*centre of mass y +([-0-9.]+) m")
    message(FATAL_ERROR "femto run ${ARGN}: exit ${code}\n${out}${err}")
  endif()
  set(lowest_text "${CMAKE_MATCH_1}")
  to_micro("${CMAKE_MATCH_2}" com)
  to_micro("${lowest_text}" lowest)
  set(COM ${com} PARENT_SCOPE)
  set(LOWEST ${lowest} PARENT_SCOPE)
  message(STATUS "femto run ${ARGN}: centre of mass y ${com} um, lowest vertex y ${lowest} um")
endfunction()

run_house(--frames 334)
set(rest ${COM})
run_house(--frames 341 --impulse-at 10)
math(EXPR rise "${COM} - ${rest}")
set(failures "")
if(rise LESS 150000 OR rise GREATER 250000)
  string(APPEND failures "seeds' jump: the centre of mass rose ${rise} um, expected 150000 to 250000\n")
endif()
if(NOT LOWEST GREATER -2990000)
  string(APPEND failures "seeds' jump: the lowest vertex is at ${LOWEST} um, still on the floor at -3 m\n")
endif()
run_house(--frames 341 --impulse-at 10 --impulse-speed 0.2)
math(EXPR rise_once "${COM} - ${rest}")
if(NOT rise_once LESS 60000)
  string(APPEND failures "--impulse-speed 0.2: the centre of mass rose ${rise_once} um, expected < 60000\n")
endif()
if(NOT failures STREQUAL "")
  message(FATAL_ERROR "${failures}")
endif()
message(STATUS "jump: rise ${rise} um (seeds), ${rise_once} um (0.2 m/s once)")
