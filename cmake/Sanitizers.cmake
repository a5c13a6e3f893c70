# HUNAV_SANITIZE=ON: every target built with AddressSanitizer (+ LeakSanitizer) and
# UndefinedBehaviorSanitizer, any UB report fatal, for running the unit and integration tests
# (README.md, "Sanitizers"; CMakePresets.json preset "asan"). Tests then need the environment of
# tools/sanitizer_env.sh (the LSan suppressions of tools/lsan.supp).
option(HUNAV_SANITIZE "build with AddressSanitizer and UndefinedBehaviorSanitizer (tests only, slow)" OFF)

if(HUNAV_SANITIZE)
  # Frame pointers for readable stacks; no recovery, so a UB report fails the test that hit it.
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_link_options(-fsanitize=address,undefined)
endif()

# Called after the components are added: LCM 1.3.1's C++ subscription callback (lcm-cpp-impl.hpp)
# calls the handler through a pointer cast GCC 12's vptr check rejects, with no project code
# involved, so the translation units that instantiate lcm::LCM::subscribe skip that one check.
function(hunav_sanitizer_exceptions)
  if(NOT HUNAV_SANITIZE)
    return()
  endif()
  set_source_files_properties(${PROJECT_SOURCE_DIR}/common/transport/src/lcm_bus.cpp
                              DIRECTORY ${PROJECT_SOURCE_DIR}/common/transport PROPERTIES COMPILE_OPTIONS -fno-sanitize=vptr)
  if(TARGET example_planner)
    target_compile_options(example_planner PRIVATE -fno-sanitize=vptr)
  endif()
  # The example planner's test compiles its header (lcm::LCM::subscribe with a handler method) too.
  if(TARGET test_planners)
    set_source_files_properties(${PROJECT_SOURCE_DIR}/tests/planners/test_example_planner.cpp
                                DIRECTORY ${PROJECT_SOURCE_DIR}/tests/planners PROPERTIES COMPILE_OPTIONS -fno-sanitize=vptr)
  endif()
  # Not built by default here: benchmarks (timings under a sanitizer mean nothing) and the Python
  # module (the interpreter is not instrumented; the python_* tests are left out). Build them by name.
  foreach(target bench_episode bench_world_tick bench_lcm_roundtrip bench_stepped bench_evaluator bench_manager
                 bench_planner _hunav)
    if(TARGET ${target})
      set_target_properties(${target} PROPERTIES EXCLUDE_FROM_ALL TRUE)
    endif()
  endforeach()
endfunction()
