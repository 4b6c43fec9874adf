# The tables the rt tests read, made by the real `spectralize table` (4 spaces x 2 modes, each
# with its -v report in NAME.log, and sRGB reflectance tables of the other models).
# Usage: cmake -DSPECTRALIZE=... -DOUT=DIR -P make_rt_tables.cmake
file(MAKE_DIRECTORY ${OUT})
foreach(entry "srgb;Linear Rec.709 (sRGB)" "rec2020;Linear Rec.2020" "acescg;ACEScg"
        "aces2065;ACES2065-1")
  list(GET entry 0 stem)
  list(GET entry 1 space)
  foreach(mode reflectance emission)
    execute_process(COMMAND ${SPECTRALIZE} table -o ${OUT}/${stem}_${mode}.spztab
                            --colorspace ${space} --mode ${mode} -v
                    RESULT_VARIABLE status ERROR_FILE ${OUT}/${stem}_${mode}.log)
    if(NOT status EQUAL 0)
      message(FATAL_ERROR "spectralize table failed for ${space} ${mode}")
    endif()
  endforeach()
endforeach()
foreach(model natural smooth paper)
  execute_process(COMMAND ${SPECTRALIZE} table -o ${OUT}/srgb_reflectance_${model}.spztab
                          --colorspace "Linear Rec.709 (sRGB)" --mode reflectance --model ${model} -q
                  RESULT_VARIABLE status)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "spectralize table failed for the ${model} model")
  endif()
endforeach()
