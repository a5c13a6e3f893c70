# shellcheck shell=bash
# Sourced before running tests of a sanitizer build by hand (README.md, "Sanitizers"; the presets of
# CMakePresets.json set the same):
#   source tools/sanitizer_env.sh && ctest --test-dir build-asan ...   (or build-tsan)
# The binaries the tests start inherit it. Every report ends the process with a non-zero exit.
hunav_repo_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:check_initialization_order=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:history_size=4"
export LSAN_OPTIONS="suppressions=${hunav_repo_root}/tools/lsan.supp:print_suppressions=0"
unset hunav_repo_root
