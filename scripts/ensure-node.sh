#!/usr/bin/env bash
# Makes sure Node.js >= 20 and npm exist (the web app in ui/ is built with them). On
# Debian/Ubuntu as root, installs nodejs and npm from the distribution when its version is
# new enough; otherwise says how to install Node 20.
set -euo pipefail
need=20
major() { node -p 'process.versions.node.split(".")[0]' 2>/dev/null || echo 0; }
ok() { command -v node >/dev/null && command -v npm >/dev/null && [ "$(major)" -ge "$need" ]; }
ok && exit 0
if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null && ! command -v node >/dev/null; then
  apt-get update -qq
  candidate=$(apt-cache policy nodejs 2>/dev/null | awk '/Candidate:/ {print $2}')
  # Versions look like 20.19.2+dfsg-1 (or 1:20...); take the major number.
  candidate_major=$(echo "${candidate#*:}" | cut -d. -f1)
  if [[ "$candidate_major" =~ ^[0-9]+$ ]] && [ "$candidate_major" -ge "$need" ]; then
    echo "Installing nodejs and npm $candidate from Debian packages..." >&2
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq nodejs npm >/dev/null
    ok && exit 0
  fi
fi
if command -v node >/dev/null; then
  found="Node.js $(node --version)$(command -v npm >/dev/null || echo ' without npm')"
else
  found="no Node.js"
fi
cat >&2 <<MSG
twinlink's web app (ui/) needs Node.js >= $need with npm; this machine has $found.
Install Node.js $need or newer, for example:
  - Debian 13 / Ubuntu 24.10 or newer:  apt-get install nodejs npm
  - older Debian/Ubuntu (NodeSource):   curl -fsSL https://deb.nodesource.com/setup_20.x | bash - && apt-get install nodejs
  - any system (nvm):                   nvm install 20
Then run the make command again.
MSG
exit 1
