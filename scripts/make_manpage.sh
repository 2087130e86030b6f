#!/usr/bin/env bash
# Writes inkline's man page (roff) from the program's own help texts: `inkline --help`, then each
# command's --help, its flag groups as subsections. Run by the build (src/CMakeLists.txt).
# Usage: scripts/make_manpage.sh INKLINE_BINARY OUT.1
set -euo pipefail
bin=$1
out=$2
version=$("$bin" --version | sed 's/^inkline //')
tmp=$(mktemp "$out.XXXXXX")
trap 'rm -f "$tmp"' EXIT

# Help text -> roff: the lines before the first blank line are a paragraph; "Title:" lines are
# subsections; "  --flag=VALUE  text" lines are tagged paragraphs, deeper-indented lines continue them.
to_roff() {
  awk '
    function esc(s) { gsub(/\\/, "\\e", s); gsub(/-/, "\\-", s); sub(/^[.'"'"']/, "\\\\&&", s); return s }
    function term(t,   name, rest) {
      if (t ~ /^-[a-z] /) return "\\fB" esc(t) "\\fR"
      name = t; rest = ""
      if (match(t, /[= ]/)) { name = substr(t, 1, RSTART - 1); rest = substr(t, RSTART) }
      if (rest ~ /^=/) return "\\fB" esc(name) "\\fR=\\fI" esc(substr(rest, 2)) "\\fR"
      return "\\fB" esc(name) "\\fR" esc(rest)
    }
    NR == 1 && /^usage:/ { next }
    /^$/ { para = 1; next }
    /^  -/ {
      line = substr($0, 3)
      if (match(line, /   */)) { t = substr(line, 1, RSTART - 1); d = substr(line, RSTART + RLENGTH) }
      else { t = line; d = "" }
      print ".TP"; print term(t); if (d != "") print esc(d)
      para = 0; next
    }
    /^                    / { sub(/^ +/, ""); print esc($0); next }
    /^[^ ].*:$/ { sub(/:$/, ""); print ".SS \"" $0 "\""; para = 0; next }
    { if (para) print ".PP"; para = 0; sub(/^ +/, ""); print esc($0) }
  '
}

{
  echo ".TH INKLINE 1 \"\" \"inkline $version\" \"User Commands\""
  echo ".SH NAME"
  echo "inkline \\- draw 3D models as line drawings, hidden lines removed"
  echo ".SH SYNOPSIS"
  for cmd in render view bench; do
    synopsis=$("$bin" "$cmd" --help | sed -n '1s/^usage: inkline //p')
    echo ".B inkline"
    echo "$synopsis" | sed 's/-/\\-/g'
    echo ".br"
  done
  echo ".B inkline"
  echo "\\-\\-help | \\-\\-version | COMMAND \\-\\-help"
  echo ".SH DESCRIPTION"
  "$bin" --help | awk '/^usage:/{exit} {print}' | sed 's/-/\\-/g'
  for cmd in render view bench; do
    echo ".SH \"INKLINE $(echo "$cmd" | tr a-z A-Z)\""
    "$bin" "$cmd" --help | to_roff
  done
  cat <<'ROFF'
.SH ENVIRONMENT
.TP
.B INKLINE_STYLES
the directory where \fB\-\-style\fR=\fINAME\fR finds \fINAME\fR.json (default: the styles installed
with inkline, \fIPREFIX\fR/share/inkline/styles beside \fIPREFIX\fR/bin/inkline).
.SH EXIT STATUS
0 on success; 1 when a file cannot be read or written or a model is refused (one line on stderr
naming the file and the problem); 2 for a usage error (an unknown command or flag, a bad value:
one line naming the flag). A failed run leaves no output file.
.SH FILES
.TP
.I PREFIX/share/inkline/styles/
the style presets (\fINAME\fR.json), their offset tables and brushes, and README.md describing the format.
.TP
.I PREFIX/share/doc/inkline/
the documentation (docs/: formats, styles, freeform surfaces, the window, the library) and example
surfaces (examples/teapot.bpt, ...).
ROFF
} > "$tmp"
mv "$tmp" "$out"
trap - EXIT
