#!/bin/bash
# Paths per SVG before and after chaining (issue 41 part 3): renders the six meshes of the issue
# with the default camera by a former `inkline` (one <polyline> per piece) and by this build (one
# <path> per stroke) and counts, per drawing, the paths, the two-point ones, those shorter than a
# pixel and the drawn length; then the same with --hidden. Writes bench/results/svg_paths.md.
# Usage: bench/svg_paths.sh [build-dir] [former-inkline]   (without a former binary: this build only;
# the meshes are read from $INKLINE_DATA_DIR/meshes, default data/meshes)
set -euo pipefail
cd "$(dirname "$0")/.."
BIN="${1:-build}/src/inkline"
BEFORE="${2:-}"
OUT=bench/results/svg_paths.md
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
DATA="${INKLINE_DATA_DIR:-data}"
MESHES="fandisk bunny00 knot1 armadillo elephant ChineseDragon-10kv"

# paths, two-point paths, paths under 1 px, total length (px) of an SVG's <polyline>s and <path>s.
count() {
    python3 - "$1" <<'PY'
import math, re, sys
svg = open(sys.argv[1]).read()
lines = []
for m in re.finditer(r'<polyline points="([^"]*)"', svg):
    lines.append([tuple(map(float, p.split(','))) for p in m.group(1).split()])
for m in re.finditer(r'<path [^>]*\bd="([^"]*)"', svg):
    d = m.group(1)
    pts = [tuple(map(float, p.split(','))) for p in d.replace('M', ' ').replace('L', ' ').replace('Z', ' ').split()]
    if d.rstrip().endswith('Z'): pts.append(pts[0])
    lines.append(pts)
length = [sum(math.dist(a, b) for a, b in zip(l, l[1:])) for l in lines]
print(len(lines), sum(len(l) == 2 for l in lines), sum(x < 1 for x in length), round(sum(length)))
PY
}

# Pixels of two PNGs (8-bit grey, RGB or RGBA, not interlaced) whose grey differs by more than 8
# and by more than 128 of 255, and the ink (sum of darkness, in fully black pixels) of each.
pngdiff() {
    python3 - "$1" "$2" <<'PY'
import zlib,struct,sys
def load(fn):
    d=open(fn,'rb').read(); pos=8; idat=b''
    while pos<len(d):
        n,=struct.unpack('>I',d[pos:pos+4]); t=d[pos+4:pos+8]; c=d[pos+8:pos+8+n]; pos+=12+n
        if t==b'IHDR': w,h,bd,ct=struct.unpack('>IIBB',c[:10])
        elif t==b'IDAT': idat+=c
    bpp={2:3,6:4,0:1,4:2}[ct]; raw=zlib.decompress(idat); stride=w*bpp; out=[]; prev=bytearray(stride); i=0
    for y in range(h):
        f=raw[i]; line=bytearray(raw[i+1:i+1+stride]); i+=1+stride
        for x in range(stride):
            a=line[x-bpp] if x>=bpp else 0; b=prev[x]; c=prev[x-bpp] if x>=bpp else 0
            if f==1: line[x]=(line[x]+a)&255
            elif f==2: line[x]=(line[x]+b)&255
            elif f==3: line[x]=(line[x]+(a+b)//2)&255
            elif f==4:
                p=a+b-c; pa,pb,pc=abs(p-a),abs(p-b),abs(p-c)
                line[x]=(line[x]+(a if pa<=pb and pa<=pc else b if pb<=pc else c))&255
        out.append(bytes(line)); prev=line
    # grey value per pixel (first channel; alpha-composite on white if rgba)
    g=[]
    for row in out:
        r=[]
        for x in range(w):
            px=row[x*bpp:(x+1)*bpp]
            v=px[0]
            if bpp==4: v=(v*px[3]+255*(255-px[3]))//255
            r.append(v)
        g.append(r)
    return w,h,g
w,h,A=load(sys.argv[1]); _,_,B=load(sys.argv[2])
diff=0; big=0; ink_a=0; ink_b=0
for y in range(h):
    for x in range(w):
        d=abs(A[y][x]-B[y][x]); diff+=d>8; big+=d>128; ink_a+=255-A[y][x]; ink_b+=255-B[y][x]
print(f"pixels differing >8: {diff}, >128: {big}, ink {ink_a/255:.0f} vs {ink_b/255:.0f}")
PY
}

pictures() {  # extra flags
    echo "| mesh | differ > 8 | differ > 128 | ink before | ink after |"
    echo "|---|---:|---:|---:|---:|"
    for m in $MESHES; do
        "$BEFORE" render "$DATA/meshes/$m.off" -o "$TMP/$m-before.png" --quiet "$@"
        "$BIN" render "$DATA/meshes/$m.off" -o "$TMP/$m-after.png" --quiet "$@"
        pngdiff "$TMP/$m-before.png" "$TMP/$m-after.png" |
            sed -E 's/pixels differing >8: ([0-9]+), >128: ([0-9]+), ink ([0-9]+) vs ([0-9]+)/| '"$m"' | \1 | \2 | \3 | \4 |/'
    done
}

table() {  # extra flags
    echo "| mesh | pieces (JSON) | paths before | two-point | < 1 px | length px | paths after | two-point | < 1 px | length px | specks dropped | after / before |"
    echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    for m in $MESHES; do
        "$BIN" render "$DATA/meshes/$m.off" -o "$TMP/$m.json" --quiet "$@"
        pieces=$(python3 -c "import json,sys; print(len(json.load(open(sys.argv[1]))['polylines']))" "$TMP/$m.json")
        specks=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['stats']['specks_dropped'])" "$TMP/$m.json")
        "$BIN" render "$DATA/meshes/$m.off" -o "$TMP/$m-after.svg" --quiet "$@"
        read -r a2 a2p a1 al <<<"$(count "$TMP/$m-after.svg")"
        if [ -n "$BEFORE" ]; then
            "$BEFORE" render "$DATA/meshes/$m.off" -o "$TMP/$m-before.svg" --quiet "$@"
            read -r b2 b2p b1 bl <<<"$(count "$TMP/$m-before.svg")"
            ratio=$(python3 -c "print(f'{$a2 / $b2:.2f}')")
        else
            b2=-; b2p=-; b1=-; bl=-; ratio=-
        fi
        echo "| $m | $pieces | $b2 | $b2p | $b1 | $bl | $a2 | $a2p | $a1 | $al | $specks | $ratio |"
    done
}

{
    echo "# Paths per SVG drawing, before and after chaining"
    echo
    echo "Generated by \`bench/svg_paths.sh\` on $(date -u '+%Y-%m-%d %H:%M UTC'), commit $(git rev-parse --short HEAD)."
    echo "Default camera (framed), 1024 x 1024, default lines. *Before*: one \`<polyline>\` per piece"
    echo "(the JSON's pieces, clipped); *after*: one \`<path>\` per stroke (docs/editing.md). Length: the"
    echo "drawn length of all paths; it drops by the specks' length only (and where a path closes with Z)."
    echo
    echo "## Visible lines"
    echo
    table
    echo
    echo "## With hidden lines (--hidden)"
    echo
    table --hidden
    if [ -n "$BEFORE" ]; then
        echo
        echo "## The pictures: inkline's PNG before and after"
        echo
        echo "Pixels (of 1024 x 1024) whose grey level differs by more than 8 and by more than 128 of 255,"
        echo "and the ink of each picture (the sum of darkness, in fully black pixels). Differences: round"
        echo "joins where two round caps met (anti-aliasing drawn once instead of twice), and dropped specks."
        echo
        echo "### Visible lines"
        echo
        pictures
        echo
        echo "### With hidden lines"
        echo
        pictures --hidden
    fi
} > "$OUT"
echo "wrote $OUT"
