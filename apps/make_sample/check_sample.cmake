# cmake -DGENERATOR=... -DDATA_DIR=... -DWORK_DIR=... -P check_sample.cmake
# Runs tincdt_make_sample into WORK_DIR and checks that every file equals its copy in DATA_DIR.
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
execute_process(COMMAND "${GENERATOR}" "${WORK_DIR}" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "tincdt_make_sample failed (${rc})")
endif()
set(stale "")
foreach(name sample.las sample_contours.shp sample_contours.shx sample_contours.dbf
             sample_contours.prj)
  if(NOT EXISTS "${WORK_DIR}/${name}")
    message(FATAL_ERROR "tincdt_make_sample did not write ${name}")
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${WORK_DIR}/${name}"
                          "${DATA_DIR}/${name}" RESULT_VARIABLE differ)
  if(NOT differ EQUAL 0)
    list(APPEND stale "${name}")
  endif()
endforeach()
if(stale)
  message(FATAL_ERROR "data/ does not match tincdt_make_sample's output (${stale}); regenerate "
                      "with: build/release/apps/make_sample/tincdt_make_sample data/")
endif()
message(STATUS "data/ matches tincdt_make_sample's output")
