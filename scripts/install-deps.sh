#!/bin/sh
# Installs the Debian 12 packages marsyn needs, skipping the package index update when nothing is
# missing. Run as root (or through sudo).
set -eu
PACKAGES="build-essential cmake pkg-config libeigen3-dev libboost-dev libyaml-cpp-dev libcli11-dev
nlohmann-json3-dev libgtest-dev libgmock-dev
libnlopt-cxx-dev coinor-libipopt-dev libompl-dev libfcl-dev libboost-serialization-dev libboost-system-dev
libboost-filesystem-dev libboost-program-options-dev chromium
clang-14 libclang-rt-14-dev libfuzzer-14-dev python3-dev pybind11-dev python3-numpy
libopenmpi-dev openmpi-bin"
missing=""
for p in $PACKAGES; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
  echo "installing:$missing"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends $missing
else
  echo "all build dependencies are installed"
fi
