# hunav_embed_files(<target> <namespace>::<name> BASE_DIR <dir> FILES <file>...)
# Compiles the files (paths relative to BASE_DIR) into <target> as a hunav::EmbeddedFiles named
# <namespace>::<name> (common/core/include/hunav/embedded_files.hpp): a program that carries its
# built-in behavior trees, the paper's means or its web page needs no file beside it. The build
# regenerates the source when a file changes. The one way this project embeds files.
set(HUNAV_EMBED_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/embed_files.cmake)

function(hunav_embed_files target symbol)
  cmake_parse_arguments(EMBED "" "BASE_DIR" "FILES" ${ARGN})
  if(NOT EMBED_BASE_DIR OR NOT EMBED_FILES)
    message(FATAL_ERROR "hunav_embed_files(${target} ${symbol}): BASE_DIR and FILES are required")
  endif()
  string(MAKE_C_IDENTIFIER "${symbol}" id)
  set(out ${CMAKE_CURRENT_BINARY_DIR}/embedded_${id}.cpp)
  set(inputs "")
  foreach(file ${EMBED_FILES})
    list(APPEND inputs ${EMBED_BASE_DIR}/${file})
  endforeach()
  # The list travels to the script with | between names (a ; would split the argument).
  string(REPLACE ";" "|" file_arg "${EMBED_FILES}")
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DOUT=${out} -DSYMBOL=${symbol} -DBASE_DIR=${EMBED_BASE_DIR} -DFILES=${file_arg}
            -P ${HUNAV_EMBED_SCRIPT}
    DEPENDS ${inputs} ${HUNAV_EMBED_SCRIPT}
    COMMENT "Embedding ${symbol}"
    VERBATIM)
  target_sources(${target} PRIVATE ${out})
  target_link_libraries(${target} PRIVATE hunav_core)  # embedded_files.hpp
endfunction()
