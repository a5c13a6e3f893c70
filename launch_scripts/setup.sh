#!/usr/bin/env bash
# Installs what HuNav-LCM needs on Debian bookworm and builds it (Release) into build/: what a user
# runs (the processes, tools, Python packages and view), or with --all the tests and benchmarks too.
# As root it also installs the Python package `lcm` (LCM's Python API over liblcm) for Debian's Python.
# Idempotent: packages already installed are not installed again, and a configured build is reused.
#
#   bash launch_scripts/setup.sh [--all] [--no-install] [--no-build] [--build-dir DIR] [--help]
#
# Works from any directory. Installing needs root (or sudo); building does not.
set -euo pipefail

usage() {
  cat <<'EOF'
Usage: bash launch_scripts/setup.sh [--all] [--no-install] [--no-build] [--build-dir DIR]

Installs the Debian packages HuNav-LCM needs (apt-get, skipped when all are installed), then
configures and builds the project in Release mode (binaries in build/bin): the processes, tools,
Python packages (build/python) and the web view. As root, also installs the Python package `lcm`
for Debian's /usr/bin/python3 (LCM's Python API; Debian has none).

  --all            build the tests and benchmarks too (what `bash .ci/run` runs)
  --no-install     do not touch packages or install `lcm` (only build)
  --no-build       do not build (only install packages)
  --build-dir DIR  build there instead of <repo>/build (relative paths are taken from the repo root)
  -h, --help       show this help

Installing needs root; when not root, sudo is used if it is available.
EOF
}

# The packages, one per purpose:
#   LCM (C++ library, lcm-gen/lcm-logger, Java for lcm-spy, jchart2d for lcm-spy's plots; glib for pkg-config lcm),
#   libraries of the C++ code, test and benchmark frameworks, build tools, a JDK for the lcm-spy types jar,
#   and the tools the launch scripts use (ip, unshare/nsenter, ps, xvfb-run for headless lcm-spy checks).
PACKAGES=(
  liblcm-dev liblcm-bin liblcm-java libjchart2d-java libglib2.0-dev
  libbox2d-dev libyaml-cpp-dev libeigen3-dev libfmt-dev libcli11-dev libtinyxml2-dev libxxhash-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  pkg-config cmake g++ make default-jdk-headless
  iproute2 util-linux python3 procps xvfb xauth
  chromium  # the report test renders hunav_report's pages headless
  parallel libboost-dev  # batches: GNU parallel runs the matrix; Boost.Math (headers) for the Student t statistics
  pybind11-dev python3-dev python3-numpy python3-pytest  # the Python module (python/) and its tests
  libcpp-httplib-dev nlohmann-json3-dev zlib1g-dev python3-websocket python3-yaml  # hunav_view (view/) and its page tests
  shellcheck flake8 eslint  # the lints of the project's own files (tests/lint/)
  libnlopt-cxx-dev  # hunav_realism --calibrate: NLopt's BOBYQA fits the people models (realism/README.md)
)

do_install=1
do_build=1
build_all=0
build_dir=build
while [ "$#" -gt 0 ]; do
  case "$1" in
    --all) build_all=1 ;;
    --no-install) do_install=0 ;;
    --no-build) do_build=0 ;;
    --build-dir)
      [ "$#" -ge 2 ] || { echo "setup.sh: --build-dir needs a directory" >&2; exit 2; }
      build_dir=$2
      shift ;;
    --build-dir=*) build_dir=${1#--build-dir=} ;;
    -h | --help) usage; exit 0 ;;
    *) echo "setup.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done

repo_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$repo_root"

missing_packages() {
  local p status
  for p in "${PACKAGES[@]}"; do
    status=$(dpkg-query -W -f='${db:Status-Abbrev}' "$p" 2>/dev/null || true)
    case "$status" in
      ii*) ;;
      *) echo "$p" ;;
    esac
  done
}

if [ "$do_install" -eq 1 ]; then
  if ! command -v dpkg-query >/dev/null 2>&1 || ! command -v apt-get >/dev/null 2>&1; then
    echo "setup.sh: this is not a Debian system (no dpkg-query/apt-get). Install the equivalents of:" >&2
    echo "  ${PACKAGES[*]}" >&2
    echo "then run: bash launch_scripts/setup.sh --no-install" >&2
    exit 1
  fi
  mapfile -t missing < <(missing_packages)
  if [ "${#missing[@]}" -eq 0 ]; then
    echo "setup.sh: all ${#PACKAGES[@]} packages are installed"
  else
    echo "setup.sh: installing ${#missing[@]} package(s): ${missing[*]}"
    as_root=()
    if [ "$(id -u)" -ne 0 ]; then
      if command -v sudo >/dev/null 2>&1; then
        as_root=(sudo)
      else
        echo "setup.sh: installing packages needs root and sudo is not available." >&2
        echo "  As root run: apt-get update && apt-get install -y ${missing[*]}" >&2
        echo "  then: bash launch_scripts/setup.sh --no-install" >&2
        exit 1
      fi
    fi
    "${as_root[@]}" apt-get update
    "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y "${missing[@]}"
    mapfile -t still_missing < <(missing_packages)
    if [ "${#still_missing[@]}" -ne 0 ]; then
      echo "setup.sh: still not installed: ${still_missing[*]}" >&2
      exit 1
    fi
  fi
fi

if [ "$do_build" -eq 1 ]; then
  for tool in cmake make g++ pkg-config lcm-gen; do
    if ! command -v "$tool" >/dev/null 2>&1; then
      echo "setup.sh: '$tool' is not installed; run without --no-install (as root) first" >&2
      exit 1
    fi
  done
  case "$build_dir" in
    /*) build_path=$build_dir ;;
    *) build_path="$repo_root/$build_dir" ;;
  esac
  jobs=$(nproc 2>/dev/null || echo 2)
  configure=(-DCMAKE_BUILD_TYPE=Release)
  # In CI (the runner exports CI=true) a compiler warning fails the build; a user's build stays lenient.
  if [ -n "${CI:-}" ] && [ "${CI}" != false ]; then
    configure+=(-DHUNAV_WERROR=ON)
    echo "setup.sh: CI is set: compiler warnings are errors (HUNAV_WERROR=ON)"
  fi
  echo "setup.sh: configuring $build_path (Release)"
  cmake -S "$repo_root" -B "$build_path" "${configure[@]}"
  if [ "$build_all" -eq 1 ]; then
    echo "setup.sh: building everything (tests and benchmarks too) with -j$jobs"
    cmake --build "$build_path" -j"$jobs"
  else
    echo "setup.sh: building the programs (target apps; --all adds the tests) with -j$jobs"
    cmake --build "$build_path" -j"$jobs" --target apps
  fi
  if [ "$do_install" -eq 1 ] && [ -f "$build_path/python/lcm/__init__.py" ]; then
    # `import lcm` for Debian's Python, as a python3-lcm package would give it.
    if [ "$(id -u)" -eq 0 ]; then
      cmake --install "$build_path" --component python_lcm >/dev/null
      echo "setup.sh: installed the Python package lcm for /usr/bin/python3"
    else
      echo "setup.sh: not root: the Python package lcm is in $build_path/python (PYTHONPATH=$build_path/python)"
    fi
  fi
  echo "setup.sh: done; binaries in $build_path/bin, Python packages in $build_path/python"
fi
