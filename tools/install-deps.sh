#!/usr/bin/env bash
# Installs the Debian packages the build and the tests need, only those missing.
# Usage: tools/install-deps.sh            build + test dependencies (ParaView, a
#                                         virtual X server and meshio included)
#        tools/install-deps.sh --check    list what is missing, install nothing
#        tools/install-deps.sh --viz      the same (kept for old scripts)
set -euo pipefail

check=0

for a in "$@"; do
  case "$a" in
    --check) check=1 ;;
    --viz) ;;  # (the default list has the viz packages)
    *) echo "install-deps: unknown option $a (use --check, --viz)" >&2; exit 2 ;;
  esac
done

pkgs=(gfortran libc6-dev cmake make pkg-config libopenmpi-dev openmpi-bin libhdf5-openmpi-dev hdf5-tools
      liblapack-dev libfftw3-dev
      python3 python3-numpy python3-h5py python3-matplotlib python3-scipy
      paraview python3-paraview xvfb xauth python3-meshio)
# (ParaView, a virtual X server and meshio are test dependencies: the viz
# tests draw frames and read the XDMF series with them. python3-vtk9
# conflicts with python3-paraview: not listed.)

missing=()
for p in "${pkgs[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
if [ "$check" -eq 1 ]; then
  echo "missing Debian packages: ${missing[*]}"
  exit 1
fi
if [ "$(id -u)" -ne 0 ]; then
  echo "install-deps: missing Debian packages: ${missing[*]}" >&2
  echo "install-deps: run as root, or: sudo apt-get install ${missing[*]}" >&2
  exit 1
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -q
apt-get install -y -q --no-install-recommends "${missing[@]}"
