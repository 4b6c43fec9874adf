# Checks that every C and C++ source of the project follows .clang-format (the test clang_format
# and `make format-check`). The sources are kept so that Debian 12's clang-format 14 and sid's 21
# leave them alike: both lanes run this check. Invoked as: cmake -DSOURCE_DIR=dir -DCLANG_FORMAT=exe -P FormatCheck.cmake
file(GLOB_RECURSE files RELATIVE "${SOURCE_DIR}"
     "${SOURCE_DIR}/src/*.cpp" "${SOURCE_DIR}/src/*.h" "${SOURCE_DIR}/include/*.h"
     "${SOURCE_DIR}/include/*.hpp" "${SOURCE_DIR}/tests/*.cpp" "${SOURCE_DIR}/tests/*.h"
     "${SOURCE_DIR}/tests/*.c" "${SOURCE_DIR}/oiio_plugin/*.cpp" "${SOURCE_DIR}/oiio_plugin/*.h"
     "${SOURCE_DIR}/python/*.cpp" "${SOURCE_DIR}/docs/snippets/*.cpp"
     "${SOURCE_DIR}/docs/snippets/*.c")
execute_process(COMMAND "${CLANG_FORMAT}" --dry-run --Werror ${files}
                WORKING_DIRECTORY "${SOURCE_DIR}" RESULT_VARIABLE status)
list(LENGTH files count)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "clang-format: some of the ${count} files differ (run `make format`)")
endif()
message(STATUS "clang-format: ${count} files follow .clang-format")
