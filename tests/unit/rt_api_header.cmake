# include/spectralize/rt.hpp is the API a renderer reads: at most 800 lines (as `wc -l` counts
# them). OBJECTS, a unit that includes it without SPECTRALIZE_RT_IMPLEMENTATION
# (rt_api_only.cpp), defines none of the functions of rt_impl.hpp (the loader, the validator,
# the rare paths, the C API) and calls no fetch or eval4 out of line: they are inline in it.
# Usage: cmake -DHEADER=rt.hpp -DNM=nm -DOBJECTS=rt_api_only.o -P rt_api_header.cmake
file(READ ${HEADER} text)
string(REGEX MATCHALL "\n" newlines "${text}")
list(LENGTH newlines count)
if(count GREATER 800)
  message(FATAL_ERROR "${HEADER} has ${count} lines: more than 800")
endif()
execute_process(COMMAND ${NM} ${OBJECTS} RESULT_VARIABLE status OUTPUT_VARIABLE symbols)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${NM} ${OBJECTS} failed")
endif()
string(REPLACE "\n" ";" symbols "${symbols}")
set(undefined "")
foreach(line IN LISTS symbols)
  # Mangled names: TableView::open, check_meaning, slow_fetch, boundary_of_node, map_target;
  # Table::load; fetch_array; the C API.
  if(line MATCHES " [TtWwVv] .*(9TableView(4open|13check_meaning|10slow_fetch|16boundary_of_node|10map_target)|5Table4loadEPKcPc|11fetch_array|spz_table_load|spz_fetch)")
    message(FATAL_ERROR "defined without SPECTRALIZE_RT_IMPLEMENTATION: ${line}")
  endif()
  if(line MATCHES "9TableView(5fetch|11fetch_eval4)E|3spz5eval4E")
    message(FATAL_ERROR "fetch or eval4 out of line: ${line}")
  endif()
  if(line MATCHES " U .*(5Table4loadEPKcPc|9TableView10slow_fetch)")
    list(APPEND undefined "${line}")
  endif()
endforeach()
list(LENGTH undefined calls)
if(NOT calls EQUAL 2)
  message(FATAL_ERROR "expected calls to Table::load and TableView::slow_fetch, found: ${undefined}")
endif()
message(STATUS "ok: ${HEADER} has ${count} lines; the unit calls the loader and defines none of it")
