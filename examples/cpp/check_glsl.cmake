# examples/cpp/check_glsl.cmake: runs the glsl example, then compiles the shader it wrote with
# glslangValidator when one was found (VALIDATOR empty: the example's own checks only).
#   cmake -DPROGRAM=<glsl> -DWHAT=<material or --library> -DOUT=<file.frag> [-DVALIDATOR=<path>] -P check_glsl.cmake
execute_process(COMMAND ${PROGRAM} ${WHAT} ${OUT} RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${PROGRAM} ${WHAT} ${OUT}: exit status ${status}")
endif()
if(VALIDATOR)
  # The stage comes from the extension (.frag); the #version line from the example.
  execute_process(COMMAND ${VALIDATOR} ${OUT} RESULT_VARIABLE status OUTPUT_VARIABLE log ERROR_VARIABLE log)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "glslangValidator rejected ${OUT}:\n${log}")
  endif()
  message(STATUS "glslangValidator accepts ${OUT}")
else()
  message(STATUS "glslangValidator not found: ${OUT} was not compiled")
endif()
