#!/usr/bin/env bash
# The Debian package as a cluster admin uses it: cpack builds it from BUILD_DIR, its Depends must
# name Debian runtime libraries only (no -dev package), `dpkg -x` unpacks it into a scratch root,
# and the unpacked weft runs an installed example scene headless, a two-case sweep of it and
# `weft sweep --status`, with no source tree involved. With the viewer (VIEWER=1) the package must
# hold the shaders, and under xvfb-run the unpacked viewer must read them from the package.
#   tests/package/test_package.sh BUILD_DIR VIEWER
# Prints "SKIPPED: ..." (ctest: skipped) where dpkg-deb or dpkg-shlibdeps is missing.
set -euo pipefail
build=$1
viewer=$2
for tool in dpkg-deb dpkg-shlibdeps; do
  if ! command -v "$tool" >/dev/null; then
    echo "SKIPPED: $tool not found (Debian's dpkg-dev; scripts/install-deps installs it)"
    exit 0
  fi
done
scratch=$(mktemp -d "${TMPDIR:-/tmp}/weft_package.XXXXXX")
trap 'rm -rf "$scratch"' EXIT
fail() { echo "test_package: $*" >&2; exit 1; }

# The package, built outside the build folder.
if ! cpack --config "$build/CPackConfig.cmake" -B "$scratch/package" >"$scratch/cpack.log" 2>&1; then
  cat "$scratch/cpack.log" >&2
  fail "cpack failed"
fi
debs=("$scratch"/package/*.deb)
[[ ${#debs[@]} -eq 1 && -f ${debs[0]} ]] || fail "expected one .deb in $scratch/package, found: ${debs[*]}"
deb=${debs[0]}
echo "package: $(basename "$deb")"
depends=$(dpkg-deb -f "$deb" Depends)
echo "Depends: $depends"
# The package names alone, one a line ("libc6 (>= 2.34)" -> "libc6").
names=$(tr ',' '\n' <<<"$depends" | awk '{print $1}')
for library in libc6 libstdc++6 libgomp1; do
  grep -qxF "$library" <<<"$names" || fail "Depends lacks $library: $depends"
done
if grep -q -- '-dev$' <<<"$names"; then
  fail "Depends names a -dev package: $depends"
fi

root=$scratch/root
dpkg -x "$deb" "$root"
weft=$root/usr/bin/weft
share=$root/usr/share/weft
[[ -x $weft ]] || fail "no usr/bin/weft in the package"
[[ -f $share/scenes/drape_sphere.json && -f $share/sweeps/drape_stiffness.json ]] ||
  fail "no example scenes or sweeps under usr/share/weft"
[[ -f $root/usr/share/doc/weft/README.md && -f $root/usr/share/doc/weft/recording.md ]] ||
  fail "no docs under usr/share/doc/weft"
"$weft" --version

# One installed scene, shortened as the tests shorten it, run from a folder outside any checkout.
cd "$scratch"
"$weft" --headless "$share/scenes/drape_sphere.json" --out run --quiet --frames 3 \
  --set 'cloths.0.grid.resolution=[8,8]'
grep -q '"status": "complete"' run/summary.json || fail "run/summary.json does not say complete"
[[ -s run/cloth.pc2 ]] || fail "no run/cloth.pc2 written"

# A sweep of it: before running, --status says not started (exit 1); after, complete (exit 0).
cat >sweep.json <<JSON
{"scene": "$share/scenes/drape_sphere.json", "frames": 2, "set": ["cloths.0.grid.resolution=[6,6]"],
 "grid": {"cloths.0.mass_damping": [0.1, 0.4]}}
JSON
status=0
"$weft" sweep sweep.json --out sweep --status >status_before.txt || status=$?
[[ $status -eq 1 ]] || fail "weft sweep --status before the sweep: exit $status, expected 1"
grep -q "not started" status_before.txt || fail "weft sweep --status before the sweep: $(cat status_before.txt)"
"$weft" sweep sweep.json --out sweep --jobs 1 >sweep.txt 2>&1 || { cat sweep.txt >&2; fail "weft sweep failed"; }
"$weft" sweep sweep.json --out sweep --status >status_after.txt || fail "weft sweep --status: $(cat status_after.txt)"
[[ $(grep -cE '^[^ ]+ +complete( |$)' status_after.txt) -eq 2 ]] || fail "expected 2 complete cases: $(cat status_after.txt)"
cat status_after.txt

if [[ $viewer -eq 1 ]]; then
  [[ -f $share/shaders/mesh.vert && -f $share/shaders/mesh.frag ]] || fail "no shaders under usr/share/weft"
  if command -v xvfb-run >/dev/null; then
    # A shader broken in the package, not in the source tree: the viewer must fail on the package's.
    echo "this is not GLSL" >"$share/shaders/mesh.frag"
    status=0
    xvfb-run -a -s "-screen 0 1280x720x24" "$weft" "$share/scenes/default.json" --screenshot shot.png \
      --frames 1 >viewer.txt 2>&1 || status=$?
    [[ $status -ne 0 ]] || fail "the viewer ran with a broken mesh.frag in the package: not reading the package's shaders"
    grep -q "$share/shaders/mesh.frag" viewer.txt || fail "the viewer's error does not name the package's shader: $(cat viewer.txt)"
    echo "viewer: reads $share/shaders"
  else
    echo "viewer: xvfb-run not found, the installed viewer was not started"
  fi
fi
echo "test_package: ok"
