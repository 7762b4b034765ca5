# Shared helpers of the study scripts: find the binary, read fields of voussoir's JSON output.
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
bin="${VOUSSOIR:-$here/../build/voussoir}"
[ -x "$bin" ] || { echo "${0##*/}: $bin not built (cmake -S . -B build && cmake --build build)" >&2; exit 2; }
out_dir="${OUT_DIR:-$here/out}"
mkdir -p "$out_dir"
# jnum KEY JSON: the first number after "KEY": (top-level keys come first in voussoir's output)
jnum() { sed -nE "s/^[^\"]*(\"[^\"]*\"[^\"]*)*\"$1\":([-0-9.eE+]+|null).*/\2/p" <<<"$2" | head -1; }
# jcollapse KEY JSON: KEY inside the "collapse" object (null when there was no collapse)
jcollapse() { sed -nE "s/.*\"collapse\":\{[^}]*\"$1\":([-0-9.eE+]+|null).*/\1/p" <<<"$2" | head -1; }
jstr() { sed -nE "s/.*\"$1\":(\"[^\"]*\"|null).*/\1/p" <<<"$2" | head -1 | tr -d '"'; }
count() { { grep -o "\"kind\":\"$1\"" <<<"$2" || true; } | wc -l; }
