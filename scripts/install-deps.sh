#!/usr/bin/env bash
# Installs the Debian packages Nesshisen builds with, only those missing.
set -euo pipefail
pkgs=(g++ cmake ninja-build pkg-config libfmt-dev libcli11-dev catch2
      libtomlplusplus-dev nlohmann-json3-dev libpng-dev libedit-dev libz3-dev libgecode-dev python3
      libopenmpi-dev openmpi-bin) # OpenMPI: `mpirun -n K nesshi sweep|paper` (the build runs without it)
# `install-deps.sh test` (make test, and the whole build): man pages (help2man, from each command's
# --help), the Python module (headers, pybind11), its tests and example (numpy, pytest, matplotlib).
# `make demo` builds only the command line and goes without them.
[ "${1:-}" = test ] && pkgs+=(help2man python3-dev pybind11-dev python3-numpy python3-pytest python3-matplotlib)
# `install-deps.sh fuzz` (make fuzz): clang and libFuzzer too; `make test` never needs them.
[ "${1:-}" = fuzz ] && pkgs+=(clang libclang-rt-14-dev)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "installing: ${missing[*]}"
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq "${missing[@]}"
