# The library calls no C-library elementary function whose last bits differ between libms
# (glibc, musl, Apple's, MSVC's, Emscripten's) except where listed below: a step with
# fmWorldDef.crossPlatformDeterminism must give the same bits on every target
# (docs/determinism.md). The hot path calls det_math.h's fmMathLog / fmMathPow instead.
# sqrt, fabs, floor, ceil, frexp and ldexp are exact everywhere and allowed. fmin and fmax are
# not: the C libraries disagree on the sign of fmax(-0.0, +0.0); the library uses det_math.h's
# fmMin and fmMax.
# Run: cmake -DSOURCE_DIR=<repository> -P libm_calls.cmake
set(functions acos asin atan atan2 cos sin tan cosh sinh tanh acosh asinh atanh exp exp2 expm1
    log log10 log2 log1p pow cbrt hypot erf erfc tgamma lgamma fmin fmax)
# file:function pairs outside any step:
#   det_math.h log, pow: the C library's branch of fmMathLog / fmMathPow (option off)
#   mesh.c acos: a tet's dihedral angles (fmTetMesh_GetInfo; body creation reads only the
#     volume tests of fmTetMesh_GetTetQuality)
#   body_def.c cbrt: fmEstimateBodyMemory's surface estimate (a byte count, not the state)
#   fm_math.h fmax: fmMat3's scale, the largest of 0 and fabs() values, none of them -0
set(allowed "det_math.h:log" "det_math.h:pow" "mesh.c:acos" "body_def.c:cbrt" "fm_math.h:fmax")
list(JOIN functions "|" alternatives)
file(GLOB_RECURSE sources ${SOURCE_DIR}/src/*.c ${SOURCE_DIR}/src/*.h)
file(GLOB public ${SOURCE_DIR}/include/femto/*.h)
list(APPEND sources ${public})
set(found "")
foreach(source ${sources})
  get_filename_component(name ${source} NAME)
  file(STRINGS ${source} lines)
  set(number 0)
  foreach(line IN LISTS lines)
    math(EXPR number "${number} + 1")
    string(REGEX REPLACE "//.*$" "" code "${line}")
    string(REGEX MATCHALL "(^|[^A-Za-z0-9_.])(${alternatives})f?[ ]*\\(" calls "${code}")
    foreach(call IN LISTS calls)
      string(REGEX REPLACE "^[^A-Za-z]*([a-z0-9]+)f?[ ]*\\($" "\\1" function "${call}")
      list(FIND allowed "${name}:${function}" index)
      if(index EQUAL -1)
        list(APPEND found "${name}:${number}: ${function}()")
      endif()
    endforeach()
  endforeach()
endforeach()
list(LENGTH sources count)
if(count EQUAL 0)
  message(FATAL_ERROR "no sources found under ${SOURCE_DIR}/src")
endif()
if(found)
  list(JOIN found "\n  " text)
  message(FATAL_ERROR "C-library elementary functions outside det_math.c (use fmMathLog / "
          "fmMathPow, or add a det_math function):\n  ${text}")
endif()
message(STATUS "checked ${count} files: no C-library elementary function in a step")
