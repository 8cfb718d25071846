# The Python package as a pipeline installs it: `pip install --no-build-isolation .` into a fresh virtual
# environment (with the system's numpy), then `import loopsub` by name and the checks in check_package.py.
# Usage: test_install.sh REPO WORK_DIR
set -euo pipefail
repo=$1 work=$2
rm -rf "$work" && mkdir -p "$work"
/usr/bin/python3 -m venv --system-site-packages "$work/venv"
"$work/venv/bin/pip" install --no-build-isolation --no-deps --quiet "$repo"
cd "$work"  # away from the checkout, so that only the installed package can be imported
"$work/venv/bin/python" "$repo/tests/package/check_package.py"
