# Embeds every examples/*.toml into the binary, so that `cutdyn example NAME` and the
# commands' default cases need no file at run time. One generated .cpp with one raw
# string per file; the examples stay ordinary files that users can copy.
file(GLOB CUTDYN_EXAMPLE_FILES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/examples/*.toml)
list(SORT CUTDYN_EXAMPLE_FILES)
string(REPLACE ";" "|" CUTDYN_EXAMPLE_FILES_ARG "${CUTDYN_EXAMPLE_FILES}")
set(CUTDYN_EMBEDDED_EXAMPLES_CPP ${CMAKE_CURRENT_BINARY_DIR}/generated/embedded_examples.cpp)
add_custom_command(
  OUTPUT ${CUTDYN_EMBEDDED_EXAMPLES_CPP}
  COMMAND ${CMAKE_COMMAND} -DOUT=${CUTDYN_EMBEDDED_EXAMPLES_CPP}
          "-DFILES=${CUTDYN_EXAMPLE_FILES_ARG}"
          -P ${CMAKE_CURRENT_SOURCE_DIR}/cmake/write_embedded_examples.cmake
  DEPENDS ${CUTDYN_EXAMPLE_FILES} ${CMAKE_CURRENT_SOURCE_DIR}/cmake/write_embedded_examples.cmake
  COMMENT "Embedding example case files"
  VERBATIM)
