# Fail when DOC differs from `SYSTOLE --print-parameters`.
execute_process(COMMAND ${SYSTOLE} --print-parameters OUTPUT_VARIABLE printed RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "systole --print-parameters failed (${rc})")
endif()
file(READ ${DOC} documented)
if(NOT printed STREQUAL documented)
  message(FATAL_ERROR "${DOC} is stale: run scripts/update_parameter_docs and commit the result.")
endif()
