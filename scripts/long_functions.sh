#!/bin/sh
# Lists every function (and lambda) in src/ longer than N lines (default 100), longest first:
# "lines  file:start  name". Measured with universal-ctags (start line and end: field).
# Usage: scripts/long_functions.sh [N] [DIR]   (DIR relative to the repository root; default src)
set -eu
cd "$(dirname "$0")/.."
limit=${1:-100}
dir=${2:-src}
command -v ctags >/dev/null || { echo "long_functions.sh: needs universal-ctags" >&2; exit 2; }
ctags --languages=C++ --langmap=C++:+.hpp --kinds-C++=f --fields=+ne -R -f - "$dir" |
    awk -F'\t' -v limit="$limit" '
    {
        start = ""; end = ""
        for (i = 4; i <= NF; ++i) {
            if ($i ~ /^line:/) start = substr($i, 6)
            else if ($i ~ /^end:/) end = substr($i, 5)
        }
        if (start == "" || end == "") next
        n = end - start + 1
        if (n > limit) printf "%5d  %s:%s  %s\n", n, $2, start, $1
    }' | sort -k1,1nr -k2,2
