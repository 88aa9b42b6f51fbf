#!/usr/bin/env bash
# Counts the includes that run against the floors (docs/ARCHITECTURE.md): a file may include its
# own floor and those below it, never one above. Floors, low to high:
#   base/ < globe/ < formats/ < engine/ < layers/ < ui/ < tools/
# (shaders/shared is a side floor: its C++/GLSL headers include only each other). Within the
# floors: engine/gpu and engine/scene do not include each other or engine/render; a layer's
# folder does not include another layer's folder (layers/BuiltinLayers lists them all); globe/,
# formats/ and engine/scene include no Vulkan. Prints each offence and the count; exits 1 when
# there is any.
#   usage: tools/check-floors.sh [REPO_ROOT]
set -uo pipefail
cd "${1:-$(dirname "$0")/..}"

floor() {   # floor number of a path, or -1 when it is no floor (shaders, system headers)
  case "$1" in
    base/*) echo 0 ;; globe/*) echo 1 ;; formats/*) echo 2 ;; engine/*) echo 3 ;;
    layers/*) echo 4 ;; ui/*) echo 5 ;; tools/*) echo 6 ;; *) echo -1 ;;
  esac
}

offences=0
report() { echo "  $1"; offences=$((offences + 1)); }

while IFS= read -r file; do
  from=$(floor "$file")
  [ "$from" -ge 0 ] || continue
  while IFS= read -r line; do
    target=$(sed -E 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*[<"]([^">]+)[">].*/\1/' <<<"$line")
    to=$(floor "$target")
    if [ "$to" -gt "$from" ]; then report "$file includes $target (a higher floor)"; continue; fi
    case "$file:$target" in
      engine/gpu/*:engine/scene/* | engine/gpu/*:engine/render/* | engine/scene/*:engine/gpu/* | engine/scene/*:engine/render/*)
        report "$file includes $target (engine/gpu and engine/scene stand side by side under engine/render)" ;;
    esac
    if [[ "$file" == layers/*/* && "$target" == layers/*/* ]]; then
      [ "$(cut -d/ -f2 <<<"$file")" = "$(cut -d/ -f2 <<<"$target")" ] || report "$file includes $target (another layer's folder)"
    fi
    if [[ "$file" == globe/* || "$file" == formats/* || "$file" == engine/scene/* ]] && [[ "$target" == vulkan/* ]]; then
      report "$file includes $target (this floor builds without Vulkan)"
    fi
  done < <(grep -E '^[[:space:]]*#[[:space:]]*include[[:space:]]*[<"]' "$file")
done < <(
  if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
    git ls-files base globe formats engine layers ui tools
  else
    find base globe formats engine layers ui tools -type f
  fi | grep -E '\.(h|hpp|cpp)$')

echo "check-floors: $offences include(s) against the floors"
[ "$offences" -eq 0 ]
