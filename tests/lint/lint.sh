#!/usr/bin/env bash
# lint.sh shell|python|js: runs the project's linter for that language on every such file of the
# repository and fails on any finding. shell: shellcheck (settings in .shellcheckrc) on every *.sh and
# every file with a bash/sh shebang (.ci/run). python: flake8 (settings in .flake8) on every *.py and
# every file with a python shebang. js: eslint (settings in .eslintrc.json) on every *.js (the browser's
# scripts: view/web, report/assets).
# The files are git's list (tracked files); in a copy without .git, every file outside the build
# folders. A missing linter is a failure: bash launch_scripts/setup.sh installs it (Debian package).
set -euo pipefail

kind=${1:-}
repo=$(cd "$(dirname "$(readlink -f "${BASH_SOURCE[0]}")")/../.." && pwd -P)
cd "$repo"

# repo_files: the repository's files, one per line, relative to its root.
repo_files() {
  if [ "$(git rev-parse --show-toplevel 2>/dev/null)" = "$repo" ]; then
    git ls-files
  else  # a copy without .git: the sources, not the build folders
    find . \( -path './build*' -o -path './.git' \) -prune -o -type f -print | sed 's|^\./||'
  fi | while IFS= read -r f; do [ -f "$f" ] && printf '%s\n' "$f"; done
}

# has_shebang FILE REGEX: the file's first line is a #! line whose interpreter matches REGEX.
has_shebang() {
  local first
  IFS= read -r first <"$1" 2>/dev/null || true
  [[ $first =~ ^#!.*$2 ]]
}

# need TOOL PACKAGE: fail, naming the Debian package, when TOOL is not installed.
need() {
  command -v "$1" >/dev/null 2>&1 && return 0
  echo "lint_$kind: '$1' is not installed (Debian package $2; bash launch_scripts/setup.sh installs it)" >&2
  exit 1
}

files=()
case "$kind" in
  shell)
    need shellcheck shellcheck
    while IFS= read -r f; do
      case "$f" in
        *.sh | *.bash) files+=("$f") ;;
        *) if has_shebang "$f" '(/|env +)(ba|da)?sh( |$)'; then files+=("$f"); fi ;;
      esac
    done < <(repo_files)
    lint=(shellcheck --format=gcc)
    ;;
  python)
    need flake8 flake8
    while IFS= read -r f; do
      case "$f" in
        *.py) files+=("$f") ;;
        *) if has_shebang "$f" 'python'; then files+=("$f"); fi ;;
      esac
    done < <(repo_files)
    lint=(flake8)
    ;;
  js)
    need eslint eslint
    while IFS= read -r f; do
      case "$f" in
        *.js) files+=("$f") ;;
      esac
    done < <(repo_files)
    # Debian's eslint loads its modules from /usr/share/nodejs, where Debian's node looks by itself; a
    # node from elsewhere (NodeSource's) does not.
    export NODE_PATH=/usr/share/nodejs${NODE_PATH:+:$NODE_PATH}
    lint=(eslint --format unix)
    ;;
  *)
    echo "usage: lint.sh shell|python|js" >&2
    exit 2 ;;
esac

[ "${#files[@]}" -gt 0 ] || { echo "lint_$kind: no files found under $repo" >&2; exit 1; }
if "${lint[@]}" "${files[@]}"; then
  echo "lint_$kind: ${#files[@]} files clean (${lint[0]})"
else
  echo "lint_$kind: ${lint[0]} found problems in the files above (${#files[@]} files checked)" >&2
  exit 1
fi
