#!/usr/bin/env bash
# Installs the Debian packages caustica needs (build, tests, preview under Xvfb, gnuplot for
# bench/trade plots, POV-Ray for bench/peers, clang for the sanitized suite of scripts/test.sh and,
# with libFuzzer and llvm-symbolizer, for scripts/fuzz.sh, Open MPI for `mpirun caustica render`);
# does nothing when all are present.
set -euo pipefail
packages=(build-essential cmake pkg-config ninja-build libglfw3-dev libimgui-dev libosmesa6-dev
          libglm-dev libpng-dev liblua5.4-dev libembree-dev libtbb-dev libnanoflann-dev
          libstb-dev libgtest-dev libbenchmark-dev libcli11-dev libopenexr-dev xvfb xauth xdotool
          povray gnuplot-nox clang libclang-rt-14-dev llvm openmpi-bin libopenmpi-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing: ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get -o DPkg::Lock::Timeout=600 update -q
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get -o DPkg::Lock::Timeout=600 install -y -q \
    --no-install-recommends "${missing[@]}"
fi
