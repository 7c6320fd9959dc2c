// The console's page, built into the program so there is nothing to install or keep in step.
// No inline script or style: the Content-Security-Policy allows only these same-origin files.
// Server data reaches the page through textContent only, never as markup, so a camera name or
// a log line cannot inject anything. {{CSRF}} and {{MESSAGE}} are filled in by the server with
// hex digits and fixed sentences only.
#pragma once

#include <string_view>

namespace holo::kiosk::console_assets {

inline constexpr std::string_view kLoginHtml = R"(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>Holopyramid console: log in</title>
<meta name="viewport" content="width=device-width, initial-scale=1">
<link rel="stylesheet" href="/console.css"></head>
<body class="login"><main>
<h1>Holopyramid</h1><p>Technician's console</p>
<form method="post" action="/login" id="login">
<label for="password">Password</label>
<input type="password" id="password" name="password" autocomplete="current-password" autofocus required>
<button type="submit" id="login-button">Log in</button>
</form>
<p class="message" id="message">{{MESSAGE}}</p>
</main></body></html>
)";

inline constexpr std::string_view kStatusHtml = R"(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>Holopyramid console</title>
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="csrf-token" content="{{CSRF}}">
<link rel="stylesheet" href="/console.css"><script src="/console.js" defer></script></head>
<body><header><h1>Holopyramid</h1><span id="state" class="badge">&hellip;</span>
<form method="post" action="/logout"><input type="hidden" name="csrf" value="{{CSRF}}">
<button type="submit" id="logout">Log out</button></form></header>
<main>
<section class="panel"><h2>Exhibit</h2>
<dl><dt>Relic</dt><dd id="relic">&ndash;</dd><dt>Next</dt><dd id="next-relic">&ndash;</dd></dl>
<ul id="exhibit-problems" class="problems"></ul>
<div class="actions">
<button data-action="next-relic" id="next-relic-button">Next relic</button>
<button data-action="relearn-background" id="relearn-button"
 title="Forget every camera's background and learn it again from the next frames: keep the floor clear">Relearn the background</button>
<button data-action="reload" id="reload-button" title="Read the configuration again, as systemctl reload does">Reload the configuration</button>
</div><p id="action-result" class="message"></p></section>
<section class="panel"><h2>Health</h2>
<dl><dt>Frame rate</dt><dd id="fps">&ndash;</dd><dt>Frame time</dt><dd id="frame-ms">&ndash;</dd>
<dt>Quality</dt><dd id="quality">&ndash;</dd><dt>Mode</dt><dd id="mode">&ndash;</dd>
<dt title="The oldest camera frame's age plus the frame time: about how long a visitor waits to see their reflection move, the HolopyramidHighLatency alert's figure">Latency (est.)</dt><dd id="latency">&ndash;</dd>
<dt>Camera skew</dt><dd id="skew">&ndash;</dd><dt>Foreground</dt><dd id="foreground">&ndash;</dd>
<dt>Up</dt><dd id="uptime">&ndash;</dd><dt>Configuration</dt><dd id="config">&ndash;</dd></dl>
<h3>Stages (ms)</h3><table id="stages"><tbody></tbody></table>
<h3>Cameras</h3><table id="cameras"><thead><tr><th>Camera</th><th>State</th><th>fps</th><th>Frames</th>
<th>Dropped</th><th>Unpaired</th><th>Pair skew</th><th>Age</th></tr></thead><tbody></tbody></table>
<h3>Recent problems</h3><ul id="errors" class="problems"></ul></section>
<section class="panel wide"><h2>The four faces</h2><div class="snapshots" id="faces"></div></section>
<section class="panel wide"><h2>The cameras</h2><div class="snapshots" id="camera-snapshots"></div></section>
<section class="panel wide"><h2>Log</h2><pre id="log"></pre></section>
</main><footer id="session"></footer></body></html>
)";

inline constexpr std::string_view kConsoleCss = R"(
body{font:14px/1.4 system-ui,sans-serif;margin:0;background:#15171a;color:#e6e6e6}
header{display:flex;align-items:center;gap:1em;padding:.5em 1em;background:#23262b}
header form{margin-left:auto}
h1{font-size:1.3em;margin:0}h2{font-size:1.1em;margin:.2em 0 .5em}h3{font-size:1em;margin:.8em 0 .3em}
main{display:flex;flex-wrap:wrap;gap:1em;padding:1em}
.panel{background:#1d2024;border-radius:6px;padding:.8em 1em;flex:1 1 380px}
.panel.wide{flex-basis:100%}
dl{display:grid;grid-template-columns:9em 1fr;margin:0}dt{color:#9aa}dd{margin:0}
table{border-collapse:collapse}td,th{padding:.1em .6em;text-align:right;white-space:nowrap}th{color:#9aa;font-weight:normal}
td:first-child,th:first-child{text-align:left}
.badge{padding:.1em .6em;border-radius:1em;background:#555}.badge.running{background:#1f7a3a}
.badge.blanked{background:#556}.badge.stale{background:#a33}
.alive{color:#6d6}.lost{color:#f66}
.snapshots{display:flex;flex-wrap:wrap;gap:.6em}
.snapshots figure{margin:0}.snapshots img{height:180px;background:#000;display:block}
.snapshots figcaption{color:#9aa;font-size:.9em}
.actions{display:flex;flex-wrap:wrap;gap:.5em;margin-top:.8em}
button{font:inherit;padding:.35em .9em;border:0;border-radius:4px;background:#2f6fb2;color:#fff;cursor:pointer}
button:disabled{opacity:.5}
pre{max-height:22em;overflow:auto;font-size:12px;margin:0;white-space:pre-wrap}
.problems{color:#f99;margin:.2em 0;padding-left:1.2em}.message{color:#fc6;min-height:1.2em}
body.login main{flex-direction:column;max-width:22em;margin:10vh auto}
body.login form{display:flex;flex-direction:column;gap:.5em}
input{font:inherit;padding:.35em}
footer{color:#777;padding:0 1em 1em}
)";

inline constexpr std::string_view kConsoleJs = R"('use strict';
const csrf = document.querySelector('meta[name="csrf-token"]').content;
const byId = (id) => document.getElementById(id);
const setText = (id, value) => { byId(id).textContent = value; };
const fixed = (v, digits) => (v === null || v === undefined) ? '\u2013' : Number(v).toFixed(digits);
let previousCameras = null;

function rows(tbody, items, cells) {
  tbody.replaceChildren(...items.map((item) => {
    const tr = document.createElement('tr');
    for (const [value, cls] of cells(item)) {
      const td = document.createElement('td');
      td.textContent = value;
      if (cls) td.className = cls;
      tr.appendChild(td);
    }
    return tr;
  }));
}

function list(ul, items) {
  ul.replaceChildren(...items.map((t) => { const li = document.createElement('li'); li.textContent = t; return li; }));
}

// One <img> per snapshot, reloaded once the previous picture has arrived, at most once a second.
function snapshot(container, kind, index, label) {
  const id = kind + '-' + index;
  if (byId(id)) return;
  const figure = document.createElement('figure');
  const img = document.createElement('img');
  img.id = id;
  img.alt = label;
  const caption = document.createElement('figcaption');
  caption.textContent = label;
  figure.append(img, caption);
  container.appendChild(figure);
  const load = () => { img.src = '/snapshot/' + kind + '/' + index + '.jpg?t=' + Date.now(); };
  img.addEventListener('load', () => setTimeout(load, 1000));
  img.addEventListener('error', () => setTimeout(load, 1000));
  load();
}

function show(status) {
  const h = status.health;
  const stale = h.seconds_since_frame > 5;
  const state = byId('state');
  state.textContent = stale ? 'no frame for ' + fixed(h.seconds_since_frame, 0) + ' s' : h.state;
  state.className = 'badge ' + (stale ? 'stale' : h.state);
  setText('relic', h.relic || '(no playlist)');
  setText('next-relic', h.next_relic || '\u2013');
  list(byId('exhibit-problems'), h.exhibit_problems || []);
  setText('fps', fixed(h.fps, 1) + ' fps');
  setText('frame-ms', fixed(h.frame_ms, 1) + ' ms (budget ' + fixed(h.frame_budget_ms, 0) + ' ms)');
  setText('quality', h.quality + ' (level ' + h.quality_level + ')');
  setText('mode', h.mode);
  const ages = (h.cameras || []).map((c) => c.last_frame_age_s);
  setText('latency', ages.length ? fixed(h.frame_ms + 1000 * Math.max(...ages), 0) + ' ms' : '\u2013');
  setText('skew', h.camera_skew_ms === null || h.camera_skew_ms === undefined ? '\u2013' : fixed(h.camera_skew_ms, 1) + ' ms');
  setText('foreground', h.foreground_share === null || h.foreground_share === undefined ? '\u2013' : fixed(100 * h.foreground_share, 0) + ' %');
  setText('uptime', fixed(h.uptime_s / 3600, 2) + ' h, ' + h.frames + ' frames');
  setText('config', h.config.source + (h.config.warning ? ' \u2013 ' + h.config.warning : ''));
  rows(byId('stages').tBodies[0], Object.entries(h.stage_ms || {}), ([name, ms]) => [[name], [fixed(ms, 1)]]);
  const now = performance.now();
  const cameras = h.cameras || [];
  rows(byId('cameras').tBodies[0], cameras, (c) => {
    const before = previousCameras && previousCameras.list.find((p) => p.name === c.name);
    const fps = before ? (c.frames - before.frames) / ((now - previousCameras.time) / 1000) : null;
    return [[c.name], [c.alive ? 'alive' : 'lost', c.alive ? 'alive' : 'lost'], [fixed(fps, 1)], [c.frames],
            [c.dropped], [c.unpaired], [fixed(c.pair_skew_ms, 1) + ' ms'], [fixed(c.last_frame_age_s, 2) + ' s']];
  });
  previousCameras = {time: now, list: cameras};
  list(byId('errors'), (h.last_errors || []).slice().reverse());
  const log = byId('log');
  const atEnd = log.scrollTop + log.clientHeight >= log.scrollHeight - 4;
  log.textContent = status.log.join('\n');
  if (atEnd) log.scrollTop = log.scrollHeight;
  cameras.forEach((c, i) => { if (i < 16) snapshot(byId('camera-snapshots'), 'camera', i, c.name); });
  setText('session', 'Session ends in ' + Math.round(status.session_s / 60) + ' min.');
}

async function poll() {
  try {
    const response = await fetch('/api/status', {cache: 'no-store'});
    if (response.status === 401) { location.reload(); return; }
    if (response.ok) show(await response.json());
  } catch (e) {
    setText('state', 'console unreachable');
  }
  setTimeout(poll, 1000);
}

async function act(button) {
  const action = button.dataset.action;
  button.disabled = true;
  try {
    const response = await fetch('/api/action/' + action, {method: 'POST', headers: {'X-CSRF-Token': csrf}});
    const body = await response.json();
    setText('action-result', response.ok ? button.textContent + ': asked.' : button.textContent + ': ' + body.error);
  } catch (e) {
    setText('action-result', button.textContent + ': the console did not answer.');
  }
  button.disabled = false;
}

for (let f = 0; f < 4; ++f) snapshot(byId('faces'), 'face', f, 'face ' + f);
for (const button of document.querySelectorAll('button[data-action]')) button.addEventListener('click', () => act(button));
poll();
)";

}  // namespace holo::kiosk::console_assets
