# lcm_add_types(TARGET <name> JAR <jar-target> FILES <.lcm files>)
# Debian's LCM 1.3.1 ships no CMake config, so the types are generated here with lcm-gen:
#   - C++ headers into ${CMAKE_CURRENT_BINARY_DIR}/cpp, exposed through an INTERFACE target;
#   - Java classes compiled and packed into a jar (for lcm-spy), when a JDK is found;
#   - Python modules into ${CMAKE_CURRENT_BINARY_DIR}/python/<PACKAGE> (lcm-gen --python), so that a
#     planner process in Python can encode and decode the messages (docs/planner_contract.md).
find_program(LCM_GEN_EXECUTABLE lcm-gen REQUIRED)
find_package(Python3 REQUIRED COMPONENTS Interpreter)

function(lcm_add_types)
  cmake_parse_arguments(ARG "" "TARGET;JAR;PACKAGE" "FILES" ${ARGN})
  set(cpp_dir ${CMAKE_CURRENT_BINARY_DIR}/cpp)
  set(java_dir ${CMAKE_CURRENT_BINARY_DIR}/java)
  set(headers "")
  set(java_sources "")
  foreach(lcm_file ${ARG_FILES})
    get_filename_component(type_name ${lcm_file} NAME_WE)
    list(APPEND headers ${cpp_dir}/${ARG_PACKAGE}/${type_name}.hpp)
    list(APPEND java_sources ${java_dir}/${ARG_PACKAGE}/${type_name}.java)
  endforeach()

  add_custom_command(
    OUTPUT ${headers}
    COMMAND ${LCM_GEN_EXECUTABLE} -x --cpp-hpath ${cpp_dir} ${ARG_FILES}
    DEPENDS ${ARG_FILES}
    WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}
    COMMENT "lcm-gen: C++ types")
  # <PACKAGE>/wire_checks.hpp: safeToDecode<T>(bytes), run before lcm-gen's decoder (see the script).
  set(wire_checks ${cpp_dir}/${ARG_PACKAGE}/wire_checks.hpp)
  set(wire_checks_script ${CMAKE_CURRENT_SOURCE_DIR}/gen_wire_checks.py)
  add_custom_command(
    OUTPUT ${wire_checks}
    COMMAND ${Python3_EXECUTABLE} ${wire_checks_script} ${wire_checks} ${ARG_PACKAGE} ${ARG_FILES}
    DEPENDS ${ARG_FILES} ${wire_checks_script}
    WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}
    COMMENT "Wire checks of the LCM types")
  list(APPEND headers ${wire_checks})
  # <PACKAGE>/wire_codec.hpp: each type's encoding after its hash, written and read inline, the byte
  # layout taken from the .lcm files (see the script).
  set(wire_codec ${cpp_dir}/${ARG_PACKAGE}/wire_codec.hpp)
  set(wire_codec_script ${CMAKE_CURRENT_SOURCE_DIR}/gen_wire_codec.py)
  add_custom_command(
    OUTPUT ${wire_codec}
    COMMAND ${Python3_EXECUTABLE} ${wire_codec_script} ${wire_codec} ${ARG_PACKAGE} ${ARG_FILES}
    DEPENDS ${ARG_FILES} ${wire_codec_script} ${wire_checks_script}
    WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}
    COMMENT "Wire codec of the LCM types")
  list(APPEND headers ${wire_codec})
  add_custom_target(${ARG_TARGET}_generate DEPENDS ${headers})

  # Python: <PACKAGE>/<type>.py and the package's __init__.py (plain `struct` code; the lcm module
  # is only needed to publish and subscribe).
  set(python_dir ${CMAKE_CURRENT_BINARY_DIR}/python)
  set(python_files ${python_dir}/${ARG_PACKAGE}/__init__.py)
  foreach(lcm_file ${ARG_FILES})
    get_filename_component(type_name ${lcm_file} NAME_WE)
    list(APPEND python_files ${python_dir}/${ARG_PACKAGE}/${type_name}.py)
  endforeach()
  add_custom_command(
    OUTPUT ${python_files}
    # lcm-gen appends to an existing __init__.py: start from none, so a removed type leaves no import.
    COMMAND ${CMAKE_COMMAND} -E rm -f ${python_dir}/${ARG_PACKAGE}/__init__.py
    COMMAND ${LCM_GEN_EXECUTABLE} -p --ppath ${python_dir} ${ARG_FILES}
    DEPENDS ${ARG_FILES}
    WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}
    COMMENT "lcm-gen: Python types")
  add_custom_target(${ARG_TARGET}_python ALL DEPENDS ${python_files})
  add_library(${ARG_TARGET} INTERFACE)
  add_dependencies(${ARG_TARGET} ${ARG_TARGET}_generate)
  # SYSTEM: generated code is not ours to keep warning-free.
  target_include_directories(${ARG_TARGET} SYSTEM INTERFACE ${cpp_dir})

  if(ARG_JAR)
    find_package(Java COMPONENTS Development)
    find_file(LCM_JAR lcm.jar PATHS /usr/share/java)
    if(Java_FOUND AND LCM_JAR)
      set(classes_dir ${CMAKE_CURRENT_BINARY_DIR}/java_classes)
      set(jar_file ${CMAKE_BINARY_DIR}/share/java/${ARG_JAR}.jar)
      add_custom_command(
        OUTPUT ${jar_file}
        COMMAND ${LCM_GEN_EXECUTABLE} -j --jpath ${java_dir} ${ARG_FILES}
        COMMAND ${CMAKE_COMMAND} -E make_directory ${classes_dir}
        COMMAND ${Java_JAVAC_EXECUTABLE} -nowarn -cp ${LCM_JAR} -d ${classes_dir} ${java_sources}
        COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_BINARY_DIR}/share/java
        COMMAND ${Java_JAR_EXECUTABLE} cf ${jar_file} -C ${classes_dir} .
        DEPENDS ${ARG_FILES}
        WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}
        COMMENT "lcm-gen: Java types jar for lcm-spy")
      add_custom_target(${ARG_JAR} ALL DEPENDS ${jar_file})
    else()
      message(WARNING "No JDK or lcm.jar: the Java types jar for lcm-spy is not built")
    endif()
  endif()
endfunction()
