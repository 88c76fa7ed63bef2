#!/usr/bin/env bash
# The Debian packages as a bench computer gets them: builds them with CPack from this build tree,
# checks their control fields and file lists, installs them, runs what they installed (gpsemu
# --help and --version, the man page, bash completion, the Python module, the example config, the
# systemd unit, a C++ consumer of the CMake package), then removes them and checks that the machine
# is as it was.
#   As root with apt-get, and gpsemu not installed already: `apt-get install ./gpsemu_*.deb
#   ./libgpsemu-dev_*.deb`, then `apt-get purge` (the maintainer scripts run: user, groups).
#   Otherwise (or with GPSEMU_DEB_TEST_MODE=extract): `dpkg -x` into a scratch root in WORK_DIR.
# Usage: deb_install_test.sh BUILD_DIR SOURCE_DIR WORK_DIR PYTHON CMAKE_GENERATOR
set -euo pipefail
build=$1 source=$2 work=$3 python=$4 generator=$5
export LC_ALL=C.UTF-8

fail() { echo "FAIL: $*" >&2; exit 1; }
step() { echo "== $*"; }
# Runs a command quietly; on failure shows its output and fails the test.
quiet() {
  local log="$work/last.log"
  if ! "$@" >"$log" 2>&1; then cat "$log" >&2; fail "$*"; fi
}

rm -rf "$work"
mkdir -p "$work/out"

step "cpack -G DEB"
(cd "$build" && quiet cpack -G DEB -B "$work/out")
debs=("$work"/out/gpsemu_*.deb)
devs=("$work"/out/libgpsemu-dev_*.deb)
[[ ${#debs[@]} -eq 1 && -f ${debs[0]} && ${#devs[@]} -eq 1 && -f ${devs[0]} ]] || fail "packages: $(ls "$work/out")"
deb=${debs[0]} dev=${devs[0]}

step "control fields"
version=$("$build/emulator/gpsemu" --version)
version=${version#gpsemu }
[[ $(dpkg-deb -f "$deb" Version) == "$version"-* ]] || fail "package version $(dpkg-deb -f "$deb" Version), gpsemu --version $version"
depends=$(dpkg-deb -f "$deb" Depends)
echo "Depends: $depends"
# From dpkg-shlibdeps (the libraries gpsemu links) and the fixed ones (adduser, python3, numpy).
for want in 'libc6 (>= ' 'libstdc++6 (>= ' libserialport0 'libgpiod2 (>= ' libspdlog libfmt libgeographiclib \
            libtomlplusplus adduser 'python3 (>= ' 'python3 (<< ' python3-numpy; do
  [[ $depends == *"$want"* ]] || fail "Depends lacks '$want'"
done
[[ $(dpkg-deb -f "$dev" Depends) == *"gpsemu (= $(dpkg-deb -f "$deb" Version))"* ]] || fail "libgpsemu-dev Depends"

step "file lists"
list=$(dpkg-deb -c "$deb" | awk '{print $6}')
devlist=$(dpkg-deb -c "$dev" | awk '{print $6}')
multiarch=$(dpkg-architecture -qDEB_HOST_MULTIARCH)
for want in ./usr/bin/gpsemu ./usr/bin/gpsemu-timing "./usr/lib/$multiarch/libgpsemu.so.0" \
            ./usr/lib/systemd/system/gpsemu@.service ./usr/lib/udev/rules.d/60-gpsemu-gpio.rules \
            ./usr/share/doc/gpsemu/copyright ./usr/share/doc/gpsemu/examples/car1.toml \
            ./usr/share/man/man1/gpsemu.1.gz ./usr/share/bash-completion/completions/gpsemu; do
  grep -qxF -- "$want" <<<"$list" || fail "gpsemu lacks $want"
done
grep -qx -- './usr/lib/python3/dist-packages/gpsemu\..*\.so' <<<"$list" || fail "gpsemu lacks the Python module"
# Nothing outside Debian's places for this package, and the development files in the -dev package.
stray=$(grep -vE "^\./usr/(|bin/.*|lib/|lib/$multiarch/(|libgpsemu\.so\.[0-9.]+)|lib/python3/(|dist-packages/.*)|lib/systemd/.*|lib/udev/.*|share/(|doc/|doc/gpsemu/.*|man/(|man1/.*)|bash-completion/.*))$" <<<"$list" || true)
[[ -z $stray ]] || fail "unexpected in gpsemu: $stray"
for want in ./usr/include/gpsemu/emulator/library/gpsemu.hpp "./usr/lib/$multiarch/cmake/gpsemu/gpsemuConfig.cmake" \
            "./usr/lib/$multiarch/libgpsemu.so" ./usr/share/doc/libgpsemu-dev/copyright; do
  grep -qxF -- "$want" <<<"$devlist" || fail "libgpsemu-dev lacks $want"
done

mode=${GPSEMU_DEB_TEST_MODE:-}
if [[ -z $mode ]]; then
  mode=extract
  if [[ $(id -u) -eq 0 ]] && command -v apt-get >/dev/null; then
    if dpkg-query -W -f='${Status}' gpsemu libgpsemu-dev 2>/dev/null | grep -q installed; then
      echo "gpsemu is installed on this machine: leaving it alone (dpkg -x into a scratch root instead)"
    else
      mode=apt
    fi
  fi
fi
echo "mode: $mode"

# What the installed files are checked with; root is / (apt) or the scratch root (extract).
check_installed() {
  local root=$1
  local bin=$root/usr/bin/gpsemu
  step "gpsemu --help, --version"
  quiet "$bin" --help
  grep -q "Usage: gpsemu" "$work/last.log" || fail "gpsemu --help"
  [[ $("$bin" --version) == "gpsemu $version" ]] || fail "installed gpsemu --version: $("$bin" --version)"
  quiet "$root/usr/bin/gpsemu-timing" --help

  step "man -l gpsemu.1.gz"
  local page=$root/usr/share/man/man1/gpsemu.1.gz
  MANWIDTH=100 man --warnings -l "$page" >"$work/man.txt" 2>"$work/man.err" || fail "man -l $page: $(cat "$work/man.err")"
  [[ ! -s $work/man.err ]] || fail "man page warnings: $(cat "$work/man.err")"
  for want in NAME SYNOPSIS --source --output --config replay calibrate; do
    grep -q -- "$want" "$work/man.txt" || fail "man page lacks $want"
  done

  step "bash completion"
  local words
  words=$(bash -c 'source "$1"; COMP_WORDS=(gpsemu --sou); COMP_CWORD=1; COMP_LINE="gpsemu --sou"; COMP_POINT=12
                   _gpsemu gpsemu --sou gpsemu; printf "%s\n" "${COMPREPLY[@]}"' _ \
          "$root/usr/share/bash-completion/completions/gpsemu")
  grep -qx -- "--source" <<<"$words" || fail "completion of --sou: $words"
  words=$(bash -c 'source "$1"; COMP_WORDS=(gpsemu rep); COMP_CWORD=1; _gpsemu gpsemu rep gpsemu
                   printf "%s\n" "${COMPREPLY[@]}"' _ "$root/usr/share/bash-completion/completions/gpsemu")
  grep -qx -- "replay" <<<"$words" || fail "completion of rep: $words"

  step "python3: import gpsemu"
  local site=$root/usr/lib/python3/dist-packages
  # -S: only the packaged directory (a gpsemu-build.pth that older set-ups left cannot shadow it).
  PYTHONPATH=$site quiet "$python" -S -c "
import gpsemu, sys
assert gpsemu.__file__.startswith('$site/'), gpsemu.__file__
assert gpsemu.__version__ == '$version', gpsemu.__version__
print(gpsemu.__version__, gpsemu.__file__)"
  cat "$work/last.log"

  step "the example config"
  quiet "$bin" --config "$root/usr/share/doc/gpsemu/examples/car1.toml" --source sim:stationary --output stdout \
    --fast --duration 1
  grep -qE 'G[PN]GGA,' "$work/last.log" || fail "example config: no GGA"

  step "a C++ consumer of the installed CMake package"
  quiet cmake -S "$source/tests/package_consumer" -B "$work/consumer" -G "$generator" -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$root/usr" -DCMAKE_FIND_PACKAGE_NO_PACKAGE_REGISTRY=ON
  quiet cmake --build "$work/consumer"
  quiet "$work/consumer/consumer"
  grep -q "gpsemu $version: 3 GGA parsed" "$work/last.log" || fail "consumer: $(cat "$work/last.log")"
}

verify_unit() {
  local unit=$1
  shift
  if ! command -v systemd-analyze >/dev/null; then
    echo "systemd-analyze: not on this machine, unit not verified"
    return
  fi
  step "systemd-analyze verify"
  quiet systemd-analyze verify "$@" "$unit"
}

if [[ $mode == extract ]]; then
  root=$work/root
  quiet dpkg -x "$deb" "$root"
  quiet dpkg -x "$dev" "$root"
  check_installed "$root"
  # The unit as installed, but starting the extracted binary (the man page is not on MANPATH).
  mkdir -p "$work/unit"
  sed "s|/usr/bin/gpsemu|$root/usr/bin/gpsemu|" "$root/usr/lib/systemd/system/gpsemu@.service" >"$work/unit/gpsemu@.service"
  verify_unit "$work/unit/gpsemu@.service" --man=no
  echo "package test (dpkg -x): OK"
  exit 0
fi

# apt: one run at a time on this machine (the lock is the dpkg directory itself: no file left).
exec 9</var/lib/dpkg
flock -w 900 9 || fail "another package test holds /var/lib/dpkg"
snapshot() {
  dpkg-query -W -f='${Package} ${Status}\n' | sort
  for f in /etc/passwd /etc/group /etc/shadow /etc/gshadow; do sha256sum "$f"; done
  ls -d /etc/gpsemu /var/lib/gpsemu /usr/share/doc/gpsemu /etc/systemd/system/*.wants/gpsemu@* 2>/dev/null || true
}
snapshot >"$work/before.txt"
# apt-get without questions, waiting for dpkg's lock when another apt-get holds it.
apt_get() { DEBIAN_FRONTEND=noninteractive apt-get -y -o DPkg::Lock::Timeout=300 "$@"; }
cleanup() {
  local rc=$?
  # Purge what this test installed, whatever failed, and the packages apt pulled in for them.
  local ours=()
  for p in gpsemu libgpsemu-dev; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -qv "not-installed" && ours+=("$p")
  done
  if ((${#ours[@]})); then
    apt_get purge "${ours[@]}" >"$work/purge.log" 2>&1 || { cat "$work/purge.log" >&2; rc=1; }
  fi
  # Pulled in: installed since the snapshot and marked automatic (what another process installs by
  # hand meanwhile is marked manual, and stays).
  local pulled
  pulled=$(comm -13 <(awk '/ installed$/{print $1}' "$work/before.txt") <(apt-mark showauto | sort))
  if [[ -n $pulled ]]; then
    # shellcheck disable=SC2086
    apt_get purge $pulled >>"$work/purge.log" 2>&1 || rc=1
  fi
  snapshot >"$work/after.txt"
  if ! diff -u "$work/before.txt" "$work/after.txt" >"$work/changed.txt"; then
    echo "FAIL: the machine changed:" >&2
    cat "$work/changed.txt" >&2
    rc=1
  fi
  if ((rc == 0)); then echo "package test (apt-get install, purge): OK"; fi
  exit $rc
}
trap cleanup EXIT

step "apt-get install $(basename "$deb") $(basename "$dev")"
quiet apt_get install --no-install-recommends "$deb" "$dev"

step "what the maintainer scripts made"
getent passwd gpsemu >/dev/null || fail "no user gpsemu"
getent group gpio >/dev/null || fail "no group gpio"
[[ -d /etc/gpsemu ]] || fail "no /etc/gpsemu"
[[ $(getent passwd gpsemu | cut -d: -f7) == */nologin ]] || fail "gpsemu has a login shell"

check_installed ""
verify_unit /usr/lib/systemd/system/gpsemu@.service

step "apt-get purge"
quiet apt_get purge gpsemu libgpsemu-dev
while read -r f; do
  f=${f#.}
  [[ -z $f || -d $f ]] || [[ ! -e $f && ! -L $f ]] || fail "left after purge: $f"
done <<<"$list"$'\n'"$devlist"
# cleanup (the EXIT trap) compares the machine with before.
