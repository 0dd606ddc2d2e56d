#!/usr/bin/env bash
# The determinism hashes: every shipped scene (scenes/*.json), run headless for the frames that
# tests/determinism/hashes.txt gives it, must record positions (its .pc2 point caches, in cloth
# order) whose SHA-256 is the one in that file. The same file is checked against the gcc release
# build (ctest) and the clang build (scripts/test), so both compilers must give the same bytes.
#   tests/determinism/check_hashes.sh WEFT             check; exit 1 naming every scene that differs
#   tests/determinism/check_hashes.sh WEFT --update    rewrite hashes.txt from WEFT (scripts/update-hashes)
# A scene with no line in hashes.txt fails the check: add it with --update.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
weft=${1:?usage: check_hashes.sh WEFT [--update]}
update=0
[[ ${2:-} == --update ]] && update=1
hash_file=$here/hashes.txt
# Frames per scene when a scene has no line yet (--update); chosen to reach contact where cheap.
default_frames=4

declare -A frames=() expected=()
while read -r scene count hash; do
  [[ -z $scene || $scene == \#* ]] && continue
  frames[$scene]=$count
  expected[$scene]=$hash
done <"$hash_file"

scratch=$(mktemp -d "${TMPDIR:-/tmp}/weft_hashes.XXXXXX")
trap 'rm -rf "$scratch"' EXIT
failed=()
lines=()
for path in "$root"/scenes/*.json; do
  scene=$(basename "$path" .json)
  count=${frames[$scene]:-$default_frames}
  out=$scratch/$scene
  # One thread: the bytes are the same on any thread count (docs/recording.md), and ctest runs
  # tests side by side.
  if ! "$weft" --headless "$path" --out "$out" --frames "$count" --threads 1 --quiet >"$scratch/$scene.log" 2>&1; then
    echo "determinism: $scene: weft failed: $(tail -3 "$scratch/$scene.log")" >&2
    failed+=("$scene")
    continue
  fi
  # The caches in the order recording.json lists the cloths.
  caches=$(sed -n 's/.*"point_cache": "\([^"]*\)".*/\1/p' "$out/recording.json")
  [[ -n $caches ]] || { echo "determinism: $scene: no point caches in $out/recording.json" >&2; failed+=("$scene"); continue; }
  hash=$(cd "$out" && cat $caches | sha256sum | cut -d' ' -f1)
  lines+=("$scene $count $hash")
  if [[ $update -eq 1 ]]; then
    echo "determinism: $scene: $count frames: $hash"
  elif [[ -z ${expected[$scene]:-} ]]; then
    echo "determinism: $scene: no hash in $hash_file (add it: scripts/update-hashes)" >&2
    failed+=("$scene")
  elif [[ $hash != "${expected[$scene]}" ]]; then
    echo "determinism: $scene: $count frames: $hash, expected ${expected[$scene]}" >&2
    failed+=("$scene")
  else
    echo "determinism: $scene: $count frames: ok"
  fi
done

if [[ $update -eq 1 ]]; then
  [[ ${#failed[@]} -eq 0 ]] || { echo "determinism: not updated: ${failed[*]} failed" >&2; exit 1; }
  {
    echo "# scene frames sha256-of-its-point-caches; written by scripts/update-hashes, checked by"
    echo "# tests/determinism/check_hashes.sh (ctest determinism_hashes, and the clang build in scripts/test)."
    printf '%s\n' "${lines[@]}"
  } >"$hash_file"
  echo "determinism: wrote $hash_file (${#lines[@]} scenes)"
  exit 0
fi
if [[ ${#failed[@]} -gt 0 ]]; then
  echo "determinism: ${#failed[@]} scene(s) differ from $hash_file with $weft: ${failed[*]}" >&2
  exit 1
fi
echo "determinism: all ${#lines[@]} scenes match $hash_file"
