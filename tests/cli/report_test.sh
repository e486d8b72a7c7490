#!/usr/bin/env bash
# report.html of `converge` and `hardcases` in a real browser (Debian's headless Chromium), loaded from disk:
# every image decodes, no script fails, clicking a header sorts the table, and a screenshot shows the page. Two
# damaged copies (an image cut short, a script error) must be caught by the same check.
# Usage: report_test.sh path/to/iblx
iblx="$1"
source "$(dirname "$0")/common.sh"
browser=$(command -v chromium || command -v chromium-browser || true)
if [ -z "$browser" ]; then
  echo "FAIL: no chromium (tools/install.sh installs Debian's chromium)"
  exit 1
fi
# A private profile and no sandbox (CI runs as root); no GPU, no network is touched: the page is a file.
chrome() { timeout 60 "$browser" --headless --no-sandbox --disable-gpu --no-first-run --user-data-dir="$tmp/profile" "$@" 2>/dev/null; }
status() { chrome --dump-dom "file://$1" | grep -o 'data-status="[^"]*"' | head -1; }

timeout 300 "$iblx" converge --brdf ggx --param roughness=0.2 --size 24x24 --method env-cdf --method mis --seq sobol \
  --seeds 2 --max-spp 64 --out-dir "$tmp/conv" > /dev/null 2>&1 || fail "converge did not run"
timeout 300 "$iblx" hardcases --case zero-half --quick --method env-cdf --seq sobol --max-spp 32 --out-dir "$tmp/hard" \
  > /dev/null 2>&1 || fail "hardcases did not run"
for page in "$tmp/conv/report.html" "$tmp/hard/report.html"; do
  [ "$(status "$page")" = 'data-status="ok"' ] && pass || fail "$page: $(status "$page")"
  # Self-contained: no reference to another file or address.
  ! grep -qE '(src|href)="(http|file|[a-z_./-]+\.png)' "$page" && pass || fail "$page refers to an outside file"
done
# converge's page holds 4 plots, the reference, 2 final images and 2 heat maps, all embedded.
images=$(grep -o 'src="data:image/png;base64,' "$tmp/conv/report.html" | wc -l)
[ "$images" -eq 9 ] && pass || fail "converge's report embeds $images images, expected 9"

chrome --hide-scrollbars --window-size=1400,2200 --screenshot="$tmp/shot.png" "file://$tmp/conv/report.html" > /dev/null
size=$(stat -c %s "$tmp/shot.png" 2>/dev/null || echo 0)
[ "$size" -gt 50000 ] && pass || fail "the screenshot is $size bytes (a blank page is about 10 KB)"

# Sorting, by a click in the real page: a wrapper page clicks the "relMSE" header twice and reports the order.
cat > "$tmp/sort.html" <<'HTML'
<!DOCTYPE html><html><body><pre id="out">waiting</pre>
<iframe id="report" src="conv/report.html"></iframe>
<script>
document.getElementById('report').addEventListener('load', () => {
  const d = document.getElementById('report').contentDocument;
  const th = Array.from(d.querySelectorAll('th')).find(h => h.textContent === 'relMSE');
  const column = th.cellIndex;
  const values = () => Array.from(d.querySelector('tbody').rows).map(r => parseFloat(r.cells[column].textContent));
  th.click();
  const up = values();
  th.click();
  const down = values();
  const sorted = (a, s) => a.every((v, i) => i === 0 || s * (v - a[i - 1]) >= 0);
  document.getElementById('out').textContent =
      'sort ' + (sorted(up, 1) && sorted(down, -1) && up[0] !== down[0] ? 'ok' : 'wrong') + ' ' + up + ' / ' + down;
});
</script></body></html>
HTML
out=$(chrome --allow-file-access-from-files --virtual-time-budget=5000 --dump-dom "file://$tmp/sort.html" | grep -o 'sort [a-z]*' | head -1)
[ "$out" = "sort ok" ] && pass || fail "clicking the relMSE header: '$out'"

# The check catches a damaged page: an image cut short, and a script error.
sed 's|base64,iVBORw0KGgo[A-Za-z0-9+/]\{40\}|base64,iVBORw0K|' "$tmp/conv/report.html" > "$tmp/conv/cut.html"
[ "$(status "$tmp/conv/cut.html")" != 'data-status="ok"' ] && pass || fail "a cut image was not detected"
sed 's|</body>|<script>undefinedFunction();</script></body>|' "$tmp/conv/report.html" > "$tmp/conv/error.html"
status "$tmp/conv/error.html" | grep -q 'script error' && pass || fail "a script error was not detected: $(status "$tmp/conv/error.html")"

echo "report: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
