#!/usr/bin/env bash
# Makes sure the Python given as $1 (>= 3.11, with venv and pip) exists; on Debian/Ubuntu
# as root, installs what is missing from the distribution's packages.
set -euo pipefail
py="${1:-python3}"
ok() { "$py" -c 'import sys, venv, ensurepip; sys.exit(sys.version_info < (3, 11))' 2>/dev/null; }
ok && exit 0
if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
  echo "Installing python3, python3-venv and python3-pip from Debian packages..." >&2
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3 python3-venv python3-pip >/dev/null
  ok && exit 0
fi
echo "twinlink needs Python >= 3.11 with the venv module ($py). Install it (Debian: apt-get install python3 python3-venv) and run again." >&2
exit 1
