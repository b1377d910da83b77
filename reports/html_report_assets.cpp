// The HTML report's style sheet and script, inline in every report.
#include "reports/html_report_parts.h"

namespace warpcheck::html {
namespace {

// Colours: red for failures, amber for errors, green for passes; everything
// else quiet greys, so that the verdicts carry the page. Rows are one grid per
// <summary>, so the table and the details are one list, each row its own toggle.
constexpr std::string_view kStyle = R"CSS(
:root { --fail: #c62828; --fail-bg: #fdecea; --error: #b26a00; --error-bg: #fff4e0; --pass: #2e7d32; --pass-bg: #eaf5eb;
  --ink: #1f2328; --muted: #5f6773; --line: #d8dce1; --soft: #f5f6f8; --link: #1a5fb4; color-scheme: light; }
* { box-sizing: border-box; }
html { -webkit-text-size-adjust: 100%; }
body { margin: 0; color: var(--ink); background: #fff;
  font: 14px/1.45 system-ui, -apple-system, "Segoe UI", Roboto, "Noto Sans", "DejaVu Sans", "Liberation Sans", Arial, sans-serif; }
code, pre, .mono { font-family: ui-monospace, "SFMono-Regular", "DejaVu Sans Mono", "Liberation Mono", Menlo, Consolas, monospace; font-size: 12.5px; }
a { color: var(--link); text-decoration: none; } a:hover { text-decoration: underline; }
[hidden] { display: none !important; }
main, .banner-inner, footer { max-width: 1360px; margin: 0 auto; padding: 0 24px; }
.banner { color: #fff; background: var(--pass); padding: 16px 0 14px; }
.banner.fail { background: var(--fail); } .banner.error { background: var(--error); } .banner.empty { background: #59616b; }
.banner h1 { margin: 0; font-size: 24px; } .banner h1 .tool { font-weight: 400; opacity: 0.85; margin-right: 10px; }
.banner p { margin: 4px 0 0; opacity: 0.95; }
h2 { font-size: 17px; margin: 26px 0 10px; padding-bottom: 6px; border-bottom: 1px solid var(--line); }
.tiles { display: flex; flex-wrap: wrap; gap: 10px; margin: 18px 0 14px; }
.tile { flex: 1 1 120px; border: 1px solid var(--line); border-radius: 8px; padding: 8px 12px; background: var(--soft); }
.tile .n { display: block; font-size: 26px; font-weight: 700; line-height: 1.15; font-variant-numeric: tabular-nums; }
.tile .l { color: var(--muted); font-size: 12px; text-transform: uppercase; letter-spacing: 0.05em; }
.tile.fail { background: var(--fail-bg); border-color: #f1b7b2; } .tile.fail .n { color: var(--fail); }
.tile.error { background: var(--error-bg); border-color: #f0d2a0; } .tile.error .n { color: var(--error); }
.tile.pass { background: var(--pass-bg); border-color: #b9dcbb; } .tile.pass .n { color: var(--pass); }
.tile.zero { background: var(--soft); border-color: var(--line); } .tile.zero .n { color: var(--muted); }
.run-info { display: grid; grid-template-columns: max-content 1fr max-content 1fr; gap: 3px 16px; margin: 0; font-size: 13px; }
.run-info dt { color: var(--muted); } .run-info dd { margin: 0; overflow-wrap: anywhere; }
.run-info dt.wide { grid-column: 1; } .run-info dd.wide { grid-column: 2 / span 3; }
table.checks { border-collapse: collapse; font-size: 13px; width: 100%; }
table.checks th, table.checks td { padding: 4px 10px 4px 0; text-align: left; vertical-align: top; border-bottom: 1px solid #eceef1; }
table.checks thead th { color: var(--muted); font-weight: 600; border-bottom: 1px solid var(--line); }
table.checks td.n { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
table.checks td.what { color: #3d434b; font-size: 12.5px; }
.bad { color: var(--fail); font-weight: 600; }
ul.weakest { margin: 0; padding: 0; list-style: none; font-size: 13px; columns: 2 520px; }
ul.weakest li { padding: 1px 0; break-inside: avoid; } ul.weakest .wm { display: inline-block; min-width: 92px; font-variant-numeric: tabular-nums; }
.note { color: var(--muted); font-size: 12.5px; }
.toolbar { position: sticky; top: 0; z-index: 2; background: #fff; display: flex; flex-wrap: wrap; gap: 8px; align-items: center;
  padding: 8px 0; border-bottom: 1px solid var(--line); }
.toolbar input[type=search] { font: inherit; flex: 1 1 260px; padding: 5px 9px; border: 1px solid #b9bfc7; border-radius: 6px; }
.toolbar select, .toolbar button { font: inherit; font-size: 13px; padding: 4px 9px; border: 1px solid var(--line); border-radius: 6px; background: var(--soft); cursor: pointer; }
.toolbar button[aria-pressed=true] { background: #2b3137; color: #fff; border-color: #2b3137; }
.toolbar .shown { color: var(--muted); font-size: 12.5px; margin-left: auto; }
.cols, details.r > summary { display: grid; grid-template-columns: 76px minmax(200px, 2.2fr) 104px 118px minmax(150px, 2fr) 64px 58px;
  gap: 0 10px; align-items: baseline; padding: 4px 10px 4px 8px; }
.cols { color: var(--muted); font-size: 12px; font-weight: 600; border-bottom: 2px solid var(--line); }
.cols span:nth-child(n+6) { text-align: right; }
section.fam { margin: 0; }
section.fam > h3 { margin: 14px 0 0; padding: 6px 8px; font-size: 13.5px; background: var(--soft); border-radius: 6px 6px 0 0;
  border-bottom: 1px solid var(--line); display: flex; flex-wrap: wrap; gap: 4px 14px; align-items: baseline; }
section.fam > h3 .fn { font-family: ui-monospace, "DejaVu Sans Mono", monospace; }
section.fam > h3 .fc { color: var(--muted); font-weight: 400; font-size: 12.5px; }
details.r { border-bottom: 1px solid #eceef1; }
details.r > summary { cursor: pointer; list-style: none; font-size: 13px; }
details.r > summary::-webkit-details-marker { display: none; }
details.r > summary:hover { background: #f7f9fb; }
details.r > summary .v::before { content: "\25B8"; color: var(--muted); display: inline-block; width: 12px; }
details.r[open] > summary .v::before { content: "\25BE"; }
details.r.fail > summary { background: var(--fail-bg); box-shadow: inset 4px 0 0 var(--fail); }
details.r.error > summary { background: var(--error-bg); box-shadow: inset 4px 0 0 var(--error); }
details.r[open] > summary { border-bottom: 1px solid #eceef1; }
summary .case { overflow-wrap: anywhere; } summary .case .fam-part { color: var(--muted); }
summary .chk { color: #3d434b; } summary .key { color: #3d434b; overflow-wrap: anywhere; }
summary .p, summary .t { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
summary .m { font-variant-numeric: tabular-nums; white-space: nowrap; font-size: 12px; overflow: hidden; text-overflow: ellipsis; }
.gauge { display: inline-block; width: 30px; height: 7px; margin-right: 6px; background: #e7eaee; border-radius: 4px; vertical-align: 1px; overflow: hidden; }
.gauge i { display: block; height: 100%; background: #8a96a6; border-radius: 4px; }
.gauge.near i { background: #d08a1a; } .gauge.over i { background: var(--fail); }
.badge { display: inline-block; min-width: 40px; text-align: center; border-radius: 4px; padding: 0 5px; font-size: 11px; font-weight: 700; letter-spacing: 0.04em; color: #fff; }
.badge.pass { background: var(--pass); } .badge.fail { background: var(--fail); } .badge.error { background: var(--error); } .badge.na { background: #8a939d; } .badge.weak { background: #a66f00; }
.body { padding: 6px 14px 14px 20px; border-left: 4px solid #e4e7eb; }
.fail > .body { border-left-color: var(--fail); } .error > .body { border-left-color: var(--error); }
.message { margin: 8px 0; padding: 7px 11px; border-radius: 6px; white-space: pre-wrap; overflow-wrap: anywhere; background: var(--soft); border: 1px solid var(--line); }
.fail .message { background: var(--fail-bg); border-color: #f1b7b2; } .error .message { background: var(--error-bg); border-color: #f0d2a0; }
.facts { display: flex; flex-wrap: wrap; gap: 2px 20px; margin: 6px 0; color: var(--muted); font-size: 12.5px; }
.facts b { color: var(--ink); font-weight: 600; font-variant-numeric: tabular-nums; }
.rerun pre { margin: 4px 0 10px; padding: 7px 11px; background: #1f2328; color: #f0f2f4; border-radius: 6px; white-space: pre-wrap; overflow-wrap: anywhere; user-select: all; }
h4 { font-size: 12px; text-transform: uppercase; letter-spacing: 0.05em; color: var(--muted); margin: 14px 0 5px; }
table.judged { border-collapse: collapse; font-size: 12.5px; }
table.judged th { text-align: left; color: var(--muted); font-weight: 600; padding: 2px 14px 2px 0; }
table.judged td { padding: 2px 14px 2px 0; border-top: 1px solid #eceef1; }
table.judged td.val { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
table.judged tr.beyond td { color: var(--fail); font-weight: 600; } table.judged tr.reported td { color: var(--muted); }
.plots { display: flex; flex-wrap: wrap; gap: 6px 26px; align-items: flex-start; }
details.across { margin: 4px 8px 8px; } details.across > summary { font-size: 12.5px; color: var(--muted); cursor: pointer; }
figure { margin: 6px 0; max-width: 100%; }
figcaption { font-weight: 600; margin-bottom: 2px; font-size: 13px; }
figure .note { max-width: 560px; margin: 2px 0 0; }
svg.plot { display: block; max-width: 100%; height: auto; }
svg.plot text { font-family: inherit; }
svg.plot .axis-label, svg.plot .panel-title { font-weight: 600; }
svg.plot .legend-title { fill: #5f6773; }
svg.plot image.cells { image-rendering: pixelated; }
.table-title { font-weight: 600; margin: 10px 0 4px; font-size: 13px; }
.table-scroll { max-width: 100%; overflow-x: auto; margin: 0 0 8px; }
@media screen { .table-scroll { max-height: 360px; overflow-y: auto; } table.evidence thead th { position: sticky; top: 0; } }
table.evidence { border-collapse: separate; border-spacing: 0; font-size: 12px; }
table.evidence th, table.evidence td { border-right: 1px solid var(--line); border-bottom: 1px solid var(--line); padding: 2px 7px; text-align: left; }
table.evidence tr > :first-child { border-left: 1px solid var(--line); } table.evidence thead th { border-top: 1px solid var(--line); }
table.evidence th { background: var(--soft); font-weight: 600; }
table.evidence td { font-family: ui-monospace, "DejaVu Sans Mono", monospace; }
details.figs > summary { cursor: pointer; color: var(--link); font-size: 12.5px; margin: 10px 0 4px; }
dl.figures { display: grid; grid-template-columns: repeat(auto-fill, minmax(250px, 1fr)); gap: 0 24px; margin: 0; font-size: 12.5px; }
dl.figures div { display: flex; justify-content: space-between; gap: 12px; border-bottom: 1px dotted var(--line); padding: 1px 0; }
dl.figures dt { color: var(--muted); overflow-wrap: anywhere; } dl.figures dd { margin: 0; font-variant-numeric: tabular-nums; white-space: nowrap; }
.empty-result { padding: 14px 8px; color: var(--muted); }
footer { color: var(--muted); font-size: 12px; padding-top: 20px; padding-bottom: 30px; }
@media (max-width: 900px) {
  .cols { display: none; }
  details.r > summary { grid-template-columns: 76px 1fr 90px; }
  summary .key { grid-column: 2 / span 2; } summary .t { display: none; }
  .run-info { grid-template-columns: max-content 1fr; } .run-info dd.wide { grid-column: auto; }
}
@media print {
  body { font-size: 10pt; }
  main, .banner-inner, footer { max-width: none; padding: 0 6mm; }
  .banner, .badge, .tile, details.r > summary, .message, .gauge, svg.plot { print-color-adjust: exact; -webkit-print-color-adjust: exact; }
  .toolbar, .needs-js { display: none !important; }
  details.r > summary, figure, dl.figures div, .tile, table.judged tr { break-inside: avoid; }
  details.r > summary { break-after: avoid; }
  .rerun pre { background: #fff; color: #000; border: 1px solid #999; }
  a { color: inherit; }
}
)CSS";

// Search and filters (a row shows when it matches every one: the search looks
// at the row's line and its message), expand and collapse, links to a row, and
// unpacking: the details of a row that is not open when the page loads are in
// pack data-p, a zlib stream of {row index: markup} in base64, inflated by the
// browser's DecompressionStream the first time one of its rows opens. Without
// script the page still shows every row, and the failures whole.
constexpr std::string_view kScript = R"JS(
(function () {
  'use strict';
  var rows = Array.prototype.slice.call(document.querySelectorAll('details.r'));
  var groups = Array.prototype.slice.call(document.querySelectorAll('section.fam'));
  var search = document.getElementById('q'), check = document.getElementById('f-check');
  var family = document.getElementById('f-family'), shown = document.getElementById('shown');
  var verdictButtons = Array.prototype.slice.call(document.querySelectorAll('button[data-verdict]'));
  var verdict = '';
  var texts = null;  // the rows' searchable text, read at the first search
  function textOf(i) {
    if (!texts) {
      texts = rows.map(function (r) {
        return (r.querySelector('summary').textContent + ' ' + (r.getAttribute('data-s') || '')).toLowerCase();
      });
    }
    return texts[i];
  }
  document.querySelectorAll('.needs-js').forEach(function (e) { e.hidden = false; });

  var packs = {};
  function pack(id) {
    if (!packs[id]) {
      var bytes = Uint8Array.from(atob(document.getElementById('pack-' + id).textContent.trim()), function (c) { return c.charCodeAt(0); });
      packs[id] = new Response(new Blob([bytes]).stream().pipeThrough(new DecompressionStream('deflate'))).json();
    }
    return packs[id];
  }
  function unpack(row) {
    var body = row.querySelector(':scope > .body'), id = row.getAttribute('data-p');
    if (id === null || !body || body.hasAttribute('data-unpacked')) { return; }
    body.setAttribute('data-unpacked', '');
    if (typeof DecompressionStream === 'undefined') {
      body.innerHTML = '<p class="note">This browser cannot unpack the details (no DecompressionStream); the JSON report has them.</p>';
      return;
    }
    pack(id).then(function (bodies) { body.innerHTML = bodies[row.id.slice(2)]; row.setAttribute('data-ready', ''); });
  }
  document.addEventListener('toggle', function (e) {
    var d = e.target;
    if (d.classList && d.classList.contains('r') && d.open) { unpack(d); }
  }, true);

  function apply() {
    var words = search.value.toLowerCase().split(/\s+/).filter(Boolean);
    var n = 0;
    rows.forEach(function (r, i) {
      var ok = (!verdict || r.getAttribute('data-v') === verdict) && (!check.value || r.getAttribute('data-c') === check.value) &&
        (!family.value || r.parentNode.getAttribute('data-f') === family.value) &&
        words.every(function (w) { return textOf(i).indexOf(w) >= 0; });
      r.hidden = !ok;
      if (ok) { n += 1; }
    });
    groups.forEach(function (g) { g.hidden = !g.querySelector('details.r:not([hidden])'); });
    shown.textContent = n === rows.length ? 'all ' + n + ' rows' : n + ' of ' + rows.length + ' rows';
    document.getElementById('no-match').hidden = n > 0;
  }
  search.addEventListener('input', apply);
  check.addEventListener('change', apply);
  family.addEventListener('change', apply);
  verdictButtons.forEach(function (b) {
    b.addEventListener('click', function () {
      verdict = b.getAttribute('data-verdict');
      verdictButtons.forEach(function (o) { o.setAttribute('aria-pressed', String(o === b)); });
      apply();
    });
  });
  document.querySelectorAll('button[data-open]').forEach(function (b) {
    b.addEventListener('click', function () {
      var open = b.getAttribute('data-open') === 'all';
      rows.forEach(function (r) { if (!r.hidden) { r.open = open; } });
    });
  });
  document.addEventListener('keydown', function (e) {
    if (e.key === '/' && document.activeElement !== search) { e.preventDefault(); search.focus(); }
  });
  function openTarget() {
    var target = location.hash ? document.getElementById(location.hash.slice(1)) : null;
    if (target && target.classList.contains('r')) { target.hidden = false; target.open = true; target.scrollIntoView(); }
  }
  window.addEventListener('hashchange', openTarget);
  shown.textContent = 'all ' + rows.length + ' rows';
  openTarget();
})();
)JS";

}  // namespace

std::string_view style_sheet() { return kStyle; }
std::string_view script() { return kScript; }

}  // namespace warpcheck::html
