#!/usr/bin/env bash
# Renders the sample HTML report in headless Chromium: the page must load without
# a single console message (no script error, nothing blocked), the inline script
# must have run, its search and filters must work on every row (render_harness.html),
# and a screenshot is left for people to look at.
#
#   render_check.sh TEST_REPORTS_BINARY OUTPUT_DIR
#
# Exit status 77 (ctest SKIP_RETURN_CODE) when no Chromium is installed
# (Debian: apt-get install chromium; .ci/install-deps installs it).
set -euo pipefail

test_binary=$1
out=$2
mkdir -p "$out"

browser=""
for candidate in chromium chromium-browser google-chrome; do
  if command -v "$candidate" > /dev/null 2>&1; then browser=$candidate; break; fi
done
if [ -z "$browser" ]; then
  echo "render_check: SKIP, no chromium installed (apt-get install chromium)"
  exit 77
fi

report="$out/report.html"
rm -f "$report" "$out/report.png" "$out/console.log" "$out/dom.html" "$out/harness.html"
WARPCHECK_SAMPLE_REPORT="$report" "$test_binary" --gtest_filter=SampleReport.WritesForRendering > /dev/null
[ -s "$report" ] || { echo "render_check: the sample report was not written"; exit 1; }

profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
# No network at all: a report that tried to fetch anything would show it as a
# console error or a broken image.
flags=(--headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking
       --disable-component-update --disable-sync --hide-scrollbars --user-data-dir="$profile"
       --host-resolver-rules="MAP * ~NOTFOUND")

timeout 60 "$browser" "${flags[@]}" --enable-logging=stderr --v=0 --dump-dom "file://$report" \
  > "$out/dom.html" 2> "$out/console.log" || { echo "render_check: chromium failed"; tail -20 "$out/console.log"; exit 1; }

status=0
if grep -E ':CONSOLE|Uncaught|net::ERR_|Failed to load' "$out/console.log"; then
  echo "render_check: the page logged the messages above"
  status=1
fi
# The DOM after loading: the results are there, and the script ran (it shows the buttons).
grep -q 'trowbridge_reitz_visible' "$out/dom.html" || { echo "render_check: results missing from the DOM"; status=1; }
grep -q '<svg' "$out/dom.html" || { echo "render_check: no plots in the DOM"; status=1; }
if grep -Eq '<button[^>]*data-open="all"[^>]*hidden' "$out/dom.html"; then
  echo "render_check: the inline script did not run"
  status=1
fi

# The reader's use of it: search, the verdict, check and family filters, a
# packed row opened (render_harness.html drives the report in a frame and
# writes what it found as JSON into its #result).
cp "$(dirname "$0")/render_harness.html" "$out/render_harness.html"
timeout 60 "$browser" "${flags[@]}" --allow-file-access-from-files --virtual-time-budget=20000 \
  --dump-dom "file://$out/render_harness.html?report.html" > "$out/harness.html" 2> /dev/null \
  || { echo "render_check: chromium failed on the harness"; exit 1; }
result=$(sed -n 's:.*<pre id="result">\(.*\)</pre>.*:\1:p' "$out/harness.html")
echo "render_check: harness $result"
case "$result" in
  *'"ok":true'*) ;;
  *) echo "render_check: the harness found problems (or did not finish)"; status=1 ;;
esac

timeout 60 "$browser" "${flags[@]}" --screenshot="$out/report.png" --window-size=1400,2200 "file://$report" \
  > /dev/null 2>&1 || { echo "render_check: screenshot failed"; exit 1; }
size=$(stat -c %s "$out/report.png" 2> /dev/null || echo 0)
if [ "$size" -lt 20000 ]; then
  echo "render_check: the screenshot is missing or blank ($size bytes)"
  status=1
fi
echo "render_check: screenshot $out/report.png ($size bytes)"
exit $status
