#!/usr/bin/env bash
# gbh_drake's two entry points; each sets up the machine first (idempotent, offline after the
# first install: packages come from PyPI and Debian only).
#
#   ./dev.sh run [SCENARIO.yaml] [gbh run options]   run a scenario (default: scenarios/default.yaml)
#   ./dev.sh test [pytest options]                   lint (ruff) and run the test suite
#   ./dev.sh docs [mkdocs serve options]             serve the documentation site on 127.0.0.1:8000
#   ./dev.sh setup                                   only set up (.venv/ at the repository root)
set -euo pipefail
cd "$(dirname "$0")"

PYTHON=${PYTHON:-python3.11}
VENV=.venv
STAMP=$VENV/.gbh-installed
MESH_STAMP=$VENV/.gbh-meshes

as_root() { if [ "$(id -u)" = 0 ]; then "$@"; else sudo "$@"; fi; }

setup_system() {
  # Python 3.11 with venv (Drake 1.51.1's newest wheels are for 3.11).
  if ! command -v "$PYTHON" >/dev/null 2>&1 || ! "$PYTHON" -c "import venv, ensurepip" 2>/dev/null; then
    echo "dev.sh: installing Python 3.11 from Debian"
    as_root apt-get update -qq
    as_root apt-get install -y -qq python3.11 python3.11-venv
  fi
  # Graphviz draws the diagrams (gbh diagram; without it only the .dot files are written).
  if ! command -v dot >/dev/null 2>&1; then
    echo "dev.sh: installing Graphviz from Debian"
    as_root apt-get update -qq
    as_root apt-get install -y -qq graphviz
  fi
  # Chromium opens the studio's page in the browser test (tests/studio/test_studio_browser.py).
  if ! command -v chromium >/dev/null 2>&1; then
    echo "dev.sh: installing Chromium from Debian"
    as_root apt-get update -qq
    as_root apt-get install -y -qq chromium
  fi
}

setup_venv() {
  [ -x "$VENV/bin/python" ] || "$PYTHON" -m venv "$VENV"
  local want
  want=$(cat requirements.lock pyproject.toml | sha256sum | cut -d' ' -f1)
  if [ ! -f "$STAMP" ] || [ "$(cat "$STAMP")" != "$want" ]; then
    echo "dev.sh: installing pinned packages into $VENV (first time: about 2 minutes)"
    "$VENV/bin/python" -m pip install -q --upgrade pip
    "$VENV/bin/python" -m pip install -q -r requirements.lock
    "$VENV/bin/python" -m pip install -q --no-deps --no-build-isolation -e .
    echo "$want" > "$STAMP"
  fi
}

setup_meshes() {
  # The third-party meshes of the shipped object sets (scenarios/object_sets/), downloaded from
  # PyPI into the cache once (gbh objects fetch; never at run time, never committed).
  local want cache
  want=$(cat scenarios/object_sets/*.yaml | sha256sum | cut -d' ' -f1)
  cache=${GBH_DRAKE_CACHE:-$HOME/.cache/gbh_drake}
  if [ ! -f "$MESH_STAMP" ] || [ "$(cat "$MESH_STAMP")" != "$want" ] || [ ! -d "$cache" ]; then
    echo "dev.sh: fetching the object sets' third-party meshes into $cache (first time: ~1 min)"
    "$VENV/bin/gbh" objects fetch
    echo "$want" > "$MESH_STAMP"
  fi
}

cmd=${1:-run}
shift || true
setup_system
setup_venv
setup_meshes
case "$cmd" in
  setup) ;;
  run)   exec "$VENV/bin/gbh" run "$@" ;;
  # pytest-xdist: one worker per core (at most 4), each test file whole on one worker
  # (tests/conftest.py schedules them; -n 0 runs in this process).
  test)  "$VENV/bin/ruff" check gbh_drake tests bench tools
         exec "$VENV/bin/python" -m pytest -n auto --maxprocesses 4 --dist loadfile "$@" ;;
  docs)  NO_MKDOCS_2_WARNING=1 exec "$VENV/bin/mkdocs" serve --dev-addr 127.0.0.1:8000 "$@" ;;
  *)     echo "usage: ./dev.sh run|test|docs|setup [args]" >&2; exit 2 ;;
esac
