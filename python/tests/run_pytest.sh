#!/usr/bin/env bash
# ctest's entry to pytest: run_pytest.sh PYTHON TEST_FILE.
# pytest's exit codes: 0 passed; 5 (no tests collected) is a failure here,
# since every file has tests; without pytest installed: skipped (77), saying so.
python="$1"; shift
if ! "$python" -c "import pytest" 2>/dev/null; then
  echo "pytest is not installed for $python (Debian: python3-pytest; scripts/install-deps installs it)"
  exit 77
fi
"$python" -m pytest -q -p no:cacheprovider "$@"
rc=$?
if [ $rc -eq 5 ]; then echo "no tests were collected from $*"; exit 1; fi
exit $rc
