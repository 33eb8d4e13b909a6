#!/usr/bin/env bash
# Seed the fuzz corpus of `table_file` from the catalogue, the test tables
# and fixtures, and a few generated and root-entry files. Run from fuzz/.
set -euo pipefail
dir=corpus/table_file
mkdir -p "$dir"
for src in ../tableau/catalogue ../tests/tables ../tableau/tests/fixtures; do
  tag=$(basename "$(dirname "$src")")-$(basename "$src")
  for f in "$src"/*.toml; do cp "$f" "$dir/$tag-$(basename "$f")"; done
done
for g in 'gauss(3)' 'radau2a(4)' 'lobatto3a3b(4)' 'lobatto3c(5)' 'radau1a(3)'; do
  printf 'generate = "%s"\n' "$g" > "$dir/generate-${g//[()]/-}.toml"
done
cat > "$dir/gauss2-roots.toml" <<'T'
name = "Gauss–Legendre 2 via roots"
let = { c0 = "root(6*x^2 - 6*x + 1, 0, 1/2)", c1 = "root(6*x^2 - 6*x + 1, 1/2, 1)" }
a = [["1/4", "c0 - 1/4"], ["c1 - 1/4", "1/4"]]
b = ["1/2", "1/2"]
claims = ["symplectic", "order = 4"]
T
cat > "$dir/cbrt-root.toml" <<'T'
name = "roots and radicals"
let = { r = "root(x^3 - x - 1, 1, 2)", s = "sqrt(2)", t = "r^2 - s/3" }
a = [["t", "0"], ["1/2", "r"]]
b = ["1/2", "1/2"]
c = ["t", "1/2 + r"]
claims = ["symplectic"]
T
echo "seeded $(ls "$dir" | wc -l) files into $dir"
