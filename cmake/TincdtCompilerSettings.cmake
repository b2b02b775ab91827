# Warnings, sanitizers and optimisation flags shared by every project target.
add_library(tincdt_settings INTERFACE)
target_compile_options(tincdt_settings INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
                                                 -Wno-sign-conversion)
if(TINCDT_WERROR)
  target_compile_options(tincdt_settings INTERFACE -Werror)
endif()
if(TINCDT_SANITIZE)
  target_compile_options(tincdt_settings INTERFACE -fsanitize=address,undefined
                                                   -fno-sanitize-recover=all -fno-omit-frame-pointer)
  target_link_options(tincdt_settings INTERFACE -fsanitize=address,undefined)
  # GCC 12 reports false -Wmaybe-uninitialized inside libstdc++ (<regex>, std::function) once
  # ASan instruments -O1 code; the plain build keeps the warning, so nothing goes unchecked.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(tincdt_settings INTERFACE -Wno-maybe-uninitialized)
  endif()
endif()
if(TINCDT_FUZZ)
  # Coverage feedback for libFuzzer in every module; the targets link -fsanitize=fuzzer.
  target_compile_options(tincdt_settings INTERFACE -fsanitize=fuzzer-no-link)
endif()
# The exact predicates rely on IEEE double rounding: no -ffast-math, no x87 excess precision.
target_compile_options(tincdt_settings INTERFACE -fno-fast-math -ffp-contract=off)

# tincdt_module(NAME SOURCES... DEPENDS mods...) : one static library per src/ folder.
function(tincdt_module name)
  cmake_parse_arguments(M "" "" "SOURCES;DEPENDS;PRIVATE_DEPENDS" ${ARGN})
  add_library(tincdt_${name} STATIC ${M_SOURCES})
  target_include_directories(tincdt_${name} PUBLIC "${PROJECT_SOURCE_DIR}/src")
  target_link_libraries(tincdt_${name} PUBLIC tincdt_settings ${M_DEPENDS} PRIVATE ${M_PRIVATE_DEPENDS})
endfunction()
