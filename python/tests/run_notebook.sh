#!/usr/bin/env bash
# Executes a notebook with nbconvert: run_notebook.sh PYTHON NOTEBOOK OUT_DIR.
# Any cell that raises fails the test (nbconvert exits non-zero).
set -euo pipefail
python="$1" notebook="$2" out="$3"
if ! "$python" -c "import nbconvert, ipykernel, matplotlib" 2>/dev/null; then
  echo "nbconvert, ipykernel or matplotlib is missing for $python (Debian: jupyter-nbconvert python3-ipykernel python3-matplotlib)"
  exit 77
fi
mkdir -p "$out"
PYDEVD_DISABLE_FILE_VALIDATION=1 "$python" -m nbconvert --to notebook --execute --ExecutePreprocessor.timeout=300 \
  --ExecutePreprocessor.kernel_name=python3 --output-dir "$out" "$notebook"
