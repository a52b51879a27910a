# Embeds the explorer's page (web/*.html, *.js, *.css) into the binary, so that `cutdyn serve`
# needs no file at run time. One generated .cpp with one raw string per file.
file(GLOB CUTDYN_WEB_FILES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/web/*.html
     ${CMAKE_CURRENT_SOURCE_DIR}/web/*.js ${CMAKE_CURRENT_SOURCE_DIR}/web/*.css)
list(SORT CUTDYN_WEB_FILES)
string(REPLACE ";" "|" CUTDYN_WEB_FILES_ARG "${CUTDYN_WEB_FILES}")
set(CUTDYN_EMBEDDED_WEB_CPP ${CMAKE_CURRENT_BINARY_DIR}/generated/embedded_web.cpp)
add_custom_command(
  OUTPUT ${CUTDYN_EMBEDDED_WEB_CPP}
  COMMAND ${CMAKE_COMMAND} -DOUT=${CUTDYN_EMBEDDED_WEB_CPP} "-DFILES=${CUTDYN_WEB_FILES_ARG}"
          -P ${CMAKE_CURRENT_SOURCE_DIR}/cmake/write_embedded_web.cmake
  DEPENDS ${CUTDYN_WEB_FILES} ${CMAKE_CURRENT_SOURCE_DIR}/cmake/write_embedded_web.cmake
  COMMENT "Embedding the explorer's page"
  VERBATIM)
