#!/usr/bin/env bash
# Installs the Debian packages the build and the tests need, only those missing.
# Usage: tools/install-deps.sh            build + test dependencies
#        tools/install-deps.sh --check    list what is missing, install nothing
#        tools/install-deps.sh --viz      also ParaView and a virtual X server
#                                         (tools/render_frame.sh); --viz --check works too
set -euo pipefail

check=0
viz=0
for a in "$@"; do
  case "$a" in
    --check) check=1 ;;
    --viz) viz=1 ;;
    *) echo "install-deps: unknown option $a (use --check, --viz)" >&2; exit 2 ;;
  esac
done

pkgs=(gfortran libc6-dev cmake make pkg-config libopenmpi-dev openmpi-bin libhdf5-openmpi-dev hdf5-tools
      liblapack-dev libfftw3-dev
      python3 python3-numpy python3-h5py python3-matplotlib python3-scipy)
if [ "$viz" -eq 1 ]; then
  pkgs+=(paraview python3-paraview xvfb xauth)
fi

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
