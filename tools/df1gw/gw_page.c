/* SPDX-License-Identifier: MPL-2.0 */
/*
 * gw_page - the status page's files (gw_page.h; its charts' script is
 * gw_page_chart.c). The page is for a technician at the panel, often on a
 * phone: the summary first, then the line, the stations, the tags with a
 * filter, charts of the last minutes, the broker, EtherNet/IP and the
 * counters. It refreshes by itself; a failed refresh says so and keeps the
 * last figures.
 *
 * The tables fit a laptop's width without breaking a word: headers stay on
 * one line, a cell wraps at spaces only (a word longer than the whole
 * table's width is the one exception, and then the table scrolls sideways
 * in its box), and a tag's reason or a station's last error is cut to one
 * line with an ellipsis, its whole text in its title (a tap opens it).
 */
#include "df1gw/gw_page.h"

#include <string.h>

static const char page_html[] =
	"<!DOCTYPE html>\n"
	"<html lang=\"en\">\n"
	"<head>\n"
	"<meta charset=\"utf-8\">\n"
	"<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
	"<title>df1gw</title>\n"
	"<link rel=\"stylesheet\" href=\"/app.css\">\n"
	"<script src=\"/chart.js\" defer></script>\n"
	"<script src=\"/app.js\" defer></script>\n"
	"</head>\n"
	"<body>\n"
	"<header><h1>df1gw <span id=\"device\"></span></h1>\n"
	"<p id=\"summary\" class=\"summary\">loading&hellip;</p>\n"
	"<p id=\"updated\" class=\"small\"></p></header>\n"
	"<main>\n"
	"<section><h2>Line</h2><div class=\"wide\"><table id=\"line\" class=\"pairs\"><tbody></tbody></table></div>"
	"</section>\n"
	"<section><h2>Stations</h2><div class=\"wide\"><table id=\"stations\"><thead><tr><th class=\"num\">Station</th>"
	"<th>State</th><th class=\"num\">Attempts</th><th class=\"num\">Failures</th><th class=\"num\">Reply</th>"
	"<th>Last answer</th><th class=\"reason\">Last error</th></tr></thead><tbody></tbody></table></div></section>\n"
	"<section><h2>Tags</h2>\n"
	"<p><label for=\"filter\">Filter</label> <input id=\"filter\" type=\"search\" autocomplete=\"off\" "
	"placeholder=\"name, address, quality\"> <span id=\"tagcount\" class=\"small\"></span></p>\n"
	"<div class=\"wide\"><table id=\"tags\"><thead><tr><th>Name</th><th>Value</th><th>Quality</th>"
	"<th class=\"reason\">Reason</th><th>Age</th><th>Address</th><th class=\"num\">Station</th></tr></thead>"
	"<tbody></tbody></table></div></section>\n"
	"<section id=\"trends\"><h2>Last minutes</h2>\n"
	"<p class=\"small\">Read every 2 s since this page opened, the last 10 minutes kept.</p>\n"
	"<div id=\"charts\" class=\"charts\"></div></section>\n"
	"<section><h2>Broker</h2><div class=\"wide\"><table id=\"broker\" class=\"pairs\"><tbody></tbody></table>"
	"</div></section>\n"
	"<section><h2>EtherNet/IP</h2><div class=\"wide\"><table id=\"eip\" class=\"pairs\"><tbody></tbody>"
	"</table></div></section>\n"
	"<section><h2>Counters</h2><div class=\"wide\"><table id=\"counters\"><thead><tr><th>Metric</th>"
	"<th>Labels</th><th class=\"num\">Value</th></tr></thead><tbody></tbody></table></div></section>\n"
	"</main>\n"
	"<footer class=\"small\">read-only &middot; <a href=\"/metrics\">/metrics</a> &middot; "
	"<a href=\"/api/status\">/api/status</a> &middot; <span id=\"version\"></span></footer>\n"
	"</body>\n"
	"</html>\n";

static const char page_css[] =
	"body{font-family:system-ui,sans-serif;margin:0 auto;max-width:72rem;padding:.5rem;color:#111;"
	"background:#fafafa}\n"
	"h1{font-size:1.3rem;margin:.3rem 0}h2{font-size:1.1rem;margin:1rem 0 .3rem}\n"
	".summary{font-weight:600}.small{font-size:.85rem;color:#555}\n"
	".wide{overflow-x:auto}\n"
	"table{border-collapse:collapse;width:100%;font-size:.9rem}\n"
	/* a word is never cut: wrap at spaces; a word wider than the table
	 * breaks rather than overflow (overflow-wrap:break-word does not make
	 * columns narrower than their longest word, anywhere would) */
	"th,td{text-align:left;padding:.2rem .4rem;border-bottom:1px solid #ddd;vertical-align:top;"
	"overflow-wrap:break-word;word-break:normal;hyphens:none}\n"
	"th{white-space:nowrap;border-bottom:2px solid #bbb}\n"
	"td.nowrap,td.age,td.num{white-space:nowrap}th.num,td.num{text-align:right}\n"
	"table.pairs td:first-child{white-space:nowrap;width:1%}\n"
	/* a long reason on one line, cut with an ellipsis; all of it in its
	 * title, and on a tap (.open) */
	".clip{display:block;max-width:min(20rem,35vw);overflow:hidden;text-overflow:ellipsis;white-space:nowrap;"
	"cursor:pointer}\n"
	".clip.open{white-space:normal;max-width:none}\n"
	/* a quarter of the table, or the clipped text's width: the rest of the
	 * width goes to the other columns (the name first) */
	"th.reason{width:25%}\n"
	"td.GOOD,td.ok,td.connected,td.up{color:#075e00}td.UNCERTAIN,td.failing,td.connecting{color:#8a5a00}\n"
	"td.BAD,td.offline,td.down,td.absent{color:#b00000;font-weight:600}\n"
	".stale{color:#b00000}input{font-size:1rem;max-width:100%}\n"
	"td.note{color:#8a5a00;font-weight:600}\n"
	".charts{display:grid;grid-template-columns:repeat(auto-fill,minmax(19rem,1fr));gap:.6rem}\n"
	"figure.chart{margin:0;padding:.3rem;background:#fff;border:1px solid #ddd}\n"
	"figure.chart figcaption{font-size:.9rem;font-weight:600}\n"
	"figure.chart svg{display:block;width:100%;height:auto}\n"
	"@media (max-width:40rem){th:nth-child(n+6),td:nth-child(n+6){display:none}}\n";

/* Every value reaches the page through textContent (never innerHTML). */
static const char page_js[] =
	"'use strict';\n"
	"(function () {\n"
	"  var last = null, opened = {};\n"
	"  function $(id) { return document.getElementById(id); }\n"
	"  function cell(tr, text, cls) {\n"
	"    var td = document.createElement('td');\n"
	"    td.textContent = text === null || text === undefined ? '' : String(text);\n"
	"    if (cls) td.className = String(cls);\n"
	"    tr.appendChild(td);\n"
	"    return td;\n"
	"  }\n"
	/* a long text cut to one line: the whole of it in the title and, on a
	 * tap, opened (remembered by key across refreshes) */
	"  function clipped(tr, text, key, cls) {\n"
	"    var td = document.createElement('td'), sp = document.createElement('span');\n"
	"    text = text === null || text === undefined ? '' : String(text);\n"
	"    sp.className = opened[key] ? 'clip open' : 'clip';\n"
	"    sp.textContent = text;\n"
	"    if (text) sp.title = text;\n"
	"    sp.addEventListener('click', function () {\n"
	"      opened[key] = !opened[key];\n"
	"      sp.className = opened[key] ? 'clip open' : 'clip';\n"
	"    });\n"
	"    if (cls) td.className = String(cls);\n"
	"    td.appendChild(sp);\n"
	"    tr.appendChild(td);\n"
	"    return td;\n"
	"  }\n"
	"  function fill(id, rows) {\n"
	"    var tb = $(id).tBodies[0], n = document.createElement('tbody');\n"
	"    rows.forEach(function (r) { n.appendChild(r); });\n"
	"    $(id).replaceChild(n, tb);\n"
	"  }\n"
	"  function pairs(id, obj) {\n"
	"    var rows = [];\n"
	"    if (!obj) { var tr = document.createElement('tr'); cell(tr, 'not configured'); rows.push(tr); }\n"
	"    else Object.keys(obj).forEach(function (k) {\n"
	"      var tr = document.createElement('tr'), v = obj[k];\n"
	"      cell(tr, k, 'key');\n"
	"      cell(tr, v === null ? '-' : typeof v === 'object' ? JSON.stringify(v) : v,\n"
	"           k === 'state' ? v : k === 'port_note' && v ? 'note' : '');\n"
	"      rows.push(tr);\n"
	"    });\n"
	"    fill(id, rows);\n"
	"  }\n"
	"  function age(s) {\n"
	"    if (s === null || s === undefined) return 'never';\n"
	"    return s < 60 ? s.toFixed(1) + ' s' : s < 3600 ? (s / 60).toFixed(1) + ' min' : (s / 3600).toFixed(1) + ' h';\n"
	"  }\n"
	"  function value(v) {\n"
	"    if (v === null || v === undefined) return '-';\n"
	"    if (Array.isArray(v)) return '[' + v.map(function (x) { return JSON.stringify(x); }).join(', ') + ']';\n"
	"    return typeof v === 'object' ? JSON.stringify(v) : String(v);\n"
	"  }\n"
	"  function tags(list) {\n"
	"    var f = $('filter').value.trim().toLowerCase(), rows = [], shown = 0;\n"
	"    list.forEach(function (t) {\n"
	"      var hay = [t.name, t.address, t.quality, t.reason, 'station ' + t.station].join(' ').toLowerCase();\n"
	"      if (f && hay.indexOf(f) < 0) return;\n"
	"      var tr = document.createElement('tr');\n"
	"      tr.setAttribute('data-tag', t.name);\n"
	"      cell(tr, t.name, 'name');\n"
	"      cell(tr, value(t.value), 'value');\n"
	"      cell(tr, t.quality, 'nowrap ' + t.quality);\n"
	"      clipped(tr, t.error ? t.reason + ': ' + t.error : t.reason, 'tag ' + t.name, 'reason');\n"
	"      cell(tr, age(t.age_s), 'age');\n"
	"      cell(tr, t.address, 'nowrap');\n"
	"      cell(tr, t.station, 'num');\n"
	"      rows.push(tr); shown++;\n"
	"    });\n"
	"    fill('tags', rows);\n"
	"    $('tagcount').textContent = shown + ' of ' + list.length;\n"
	"  }\n"
	"  function stations(list) {\n"
	"    fill('stations', list.map(function (s) {\n"
	"      var tr = document.createElement('tr');\n"
	"      cell(tr, s.station, 'num'); cell(tr, s.state, 'nowrap ' + s.state);\n"
	"      cell(tr, s.attempts, 'num'); cell(tr, s.failures, 'num');\n"
	"      cell(tr, s.last_reply_ms === null ? '-' : s.last_reply_ms + ' ms', 'num');\n"
	"      cell(tr, age(s.last_answer_age_s), 'age');\n"
	"      clipped(tr, s.last_error || '-', 'station ' + s.station, 'error');\n"
	"      return tr;\n"
	"    }));\n"
	"  }\n"
	"  function counters(list) {\n"
	"    var rows = [];\n"
	"    (list || []).forEach(function (m) {\n"
	"      m.samples.forEach(function (s) {\n"
	"        var tr = document.createElement('tr'), l = Object.keys(s.labels).map(function (k) {\n"
	"          return k + '=' + s.labels[k]; }).join(' ');\n"
	"        tr.title = m.help;\n"
	"        cell(tr, s.name); cell(tr, l); cell(tr, s.value === null ? 'NaN' : s.value, 'num');\n"
	"        rows.push(tr);\n"
	"      });\n"
	"    });\n"
	"    fill('counters', rows);\n"
	"  }\n"
	"  function show(st) {\n"
	"    last = st;\n"
	"    $('summary').textContent = st.summary;\n"
	"    $('device').textContent = st.line.device || '';\n"
	"    $('version').textContent = 'libdf1 ' + st.version + ', started ' + st.start_time;\n"
	"    $('updated').textContent = 'updated ' + st.time;\n"
	"    $('updated').className = 'small';\n"
	"    pairs('line', st.line);\n"
	"    stations(st.stations);\n"
	"    tags(st.tags);\n"
	"    pairs('broker', st.broker);\n"
	"    pairs('eip', st.eip);\n"
	"    counters(st.metrics);\n"
	"    if (window.df1charts) window.df1charts.add(st);\n"
	"  }\n"
	"  function refresh() {\n"
	"    fetch('/api/status', { cache: 'no-store' }).then(function (r) {\n"
	"      if (!r.ok) throw new Error('HTTP ' + r.status);\n"
	"      return r.json();\n"
	"    }).then(show).catch(function (e) {\n"
	"      $('updated').textContent = 'no answer from df1gw (' + e.message + '); figures below are old';\n"
	"      $('updated').className = 'small stale';\n"
	"    });\n"
	"  }\n"
	"  document.addEventListener('DOMContentLoaded', function () {\n"
	"    $('filter').addEventListener('input', function () { if (last) tags(last.tags); });\n"
	"    refresh();\n"
	"    setInterval(refresh, 2000);\n"
	"  });\n"
	"})();\n";

static const struct gw_page_file page_files[] = {
	{ "/", "text/html; charset=utf-8", page_html, sizeof page_html - 1 },
	{ "/index.html", "text/html; charset=utf-8", page_html, sizeof page_html - 1 },
	{ "/app.js", "text/javascript; charset=utf-8", page_js, sizeof page_js - 1 },
	{ "/app.css", "text/css; charset=utf-8", page_css, sizeof page_css - 1 },
};

const struct gw_page_file *gw_page_find(const char *url)
{
	for (size_t i = 0; i < sizeof page_files / sizeof page_files[0]; i++)
		if (strcmp(url, page_files[i].path) == 0)
			return &page_files[i];
	if (strcmp(url, gw_page_chart.path) == 0)
		return &gw_page_chart;
	return NULL;
}
