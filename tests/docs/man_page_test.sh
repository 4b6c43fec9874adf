#!/usr/bin/env bash
# The man page the build writes (BUILD/docs/spectralize.1, from the settings schema) renders
# with man(1) and groff without a warning, and lists every flag `spectralize --help` prints.
# Usage: man_page_test.sh BUILD_DIR
set -euo pipefail
build=$1
page=$build/docs/spectralize.1
[ -s "$page" ] || { echo "no man page at $page"; exit 1; }
warnings=$(groff -man -Tutf8 -ww -z "$page" 2>&1 || true)
[ -z "$warnings" ] || { echo "groff warns: $warnings"; exit 1; }
rendered=$(MANWIDTH=120 man -l "$page" 2>/dev/null | col -b)
[ -n "$rendered" ] || { echo "man -l rendered nothing"; exit 1; }
grep -q "^SPECTRALIZE(1)" <<<"$rendered" || { echo "no SPECTRALIZE(1) title"; exit 1; }
flags=$("$build/spectralize" --help | grep -oE '(^|[ ,])--?[a-z][a-z0-9-]*' | tr -d ' ,' | sort -u)
missing=0 count=0
for f in $flags; do
  count=$((count + 1))
  if ! grep -qE -- "(^|[^a-z0-9-])$f([^a-z0-9-]|\$)" <<<"$rendered"; then
    echo "missing from the man page: $f"
    missing=$((missing + 1))
  fi
done
echo "$count flags of --help, $missing missing from man -l $page"
[ "$count" -ge 30 ] && [ "$missing" -eq 0 ]
