// The panels around the 3D view: the searchable node list, the attribute panel (fields
// and sliders that set inputs through sinew's lazy graph), the graph panel (SVG laid out
// by sinew), the profile table, and the error overlay.

export const $ = (id) => document.getElementById(id);

function esc(s) {
  return String(s).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' }[c]));
}

/// CSS class of a node with a problem: `err` for failures and non-finite values, `warn`
/// for a status (an IK that cannot reach).
export function problemClass(kind) {
  return kind === undefined ? '' : kind === 'status' ? 'warn' : 'err';
}

export function renderNodeList(state, onPick) {
  const q = $('search').value.trim().toLowerCase();
  const ul = $('nodes');
  ul.innerHTML = '';
  for (const n of state.nodes) {
    if (q && !n.name.toLowerCase().includes(q) && !n.type.toLowerCase().includes(q)) continue;
    const li = document.createElement('li');
    li.innerHTML = `${esc(n.name)}<span class="t">${esc(n.type)}</span>`;
    li.dataset.node = n.name;
    if (n.name === state.selected) li.classList.add('sel');
    li.onclick = () => onPick(n.name);
    ul.appendChild(li);
  }
  markNodeList(state);
}

/// Marks the nodes with problems in the node list (and clears the others).
export function markNodeList(state) {
  for (const li of $('nodes').children) {
    const c = problemClass(state.problemNodes.get(li.dataset.node));
    li.classList.toggle('err', c === 'err');
    li.classList.toggle('warn', c === 'warn');
    li.title = c ? state.problems.filter((p) => p.node === li.dataset.node).map((p) => p.message).join('\n') : '';
  }
}

/// Slider range for a value: the attribute's soft range, else its hard limits, else
/// ±180 for angles, else around the value (within the hard limits either way).
function range(attr, v) {
  let lo, hi;
  if (attr.softMin !== null || attr.softMax !== null) {
    lo = attr.softMin ?? Math.min(v, attr.softMax - 1);
    hi = attr.softMax ?? Math.max(v, attr.softMin + 1);
  } else if (attr.min !== null && attr.max !== null) {
    lo = attr.min; hi = attr.max;
  } else if (attr.unit === 'Degrees') {
    lo = -180; hi = 180;
  } else {
    const span = Math.max(1, Math.abs(v) * 2);
    lo = v - span; hi = v + span;
  }
  if (attr.min !== null) lo = Math.max(lo, attr.min);
  if (attr.max !== null) hi = Math.min(hi, attr.max);
  // A round step (a power of ten, about 1/500 of the range): a slider snaps to
  // lo + k·step, so typed round values stay exact (40° with a 0.1 step, not 39.96).
  const step = hi > lo ? 10 ** Math.floor(Math.log10((hi - lo) / 500)) : 1;
  return [lo, hi, step];
}

function fmt(v) {
  if (typeof v === 'number') return Number.isInteger(v) ? String(v) : v.toPrecision(6);
  if (Array.isArray(v)) return v.map(fmt).join(', ');
  return v === null || v === undefined ? '' : String(v);
}

/// The attribute panel of `node` (from /api/node). `send(plug, text)` sets a value.
export function renderAttrs(node, send) {
  const div = $('attrs');
  div.innerHTML = `<h3>${esc(node.name)} <span class="doc">${esc(node.type)}</span></h3>
    <div class="doc">${esc(node.doc)}${node.parent ? ' · parent ' + esc(node.parent) : ''}</div><div class="edit" id="editStats"></div>`;
  for (const a of node.attrs) {
    const row = document.createElement('div');
    row.className = 'row' + (a.input ? '' : ' out');
    row.title = `${a.plug}: ${a.type}${a.keyable ? ', keyable' : ''}${a.source ? ' ← ' + a.source : ''}\n${a.doc}`;
    row.innerHTML = `<label>${esc(a.name)}${a.index !== null ? '[' + a.index + ']' : ''}</label>`;
    if (a.custom) row.classList.add('custom');
    const ctl = document.createElement('div');
    ctl.className = 'ctl';
    if (a.editable && (a.type === 'float' || a.type === 'int')) {
      ctl.append(...numberControl(a, a.value, (v) => send(a.plug, String(v)), a.keyable || a.custom));
    } else if (a.editable && a.type === 'vec3' && Array.isArray(a.value)) {
      const cur = a.value.slice();
      const sub = document.createElement('div');
      sub.style.cssText = 'display:flex;flex-direction:column;flex:1';
      for (let k = 0; k < 3; k++) {
        const line = document.createElement('div');
        line.className = 'ctl';
        line.append(...numberControl(a, cur[k], (v) => { cur[k] = v; send(a.plug, `(${cur.join(', ')})`); }, a.keyable || a.custom, k));
        sub.append(line);
      }
      ctl.append(sub);
    } else if (a.editable && a.type === 'bool') {
      const c = document.createElement('input');
      c.type = 'checkbox';
      c.checked = !!a.value;
      c.dataset.plug = a.plug;
      c.onchange = () => send(a.plug, c.checked ? 'true' : 'false');
      ctl.append(c);
    } else if (a.editable && a.type === 'enum') {
      const s = document.createElement('select');
      s.dataset.plug = a.plug;
      a.enum.forEach((name, i) => { const o = new Option(name, name); o.selected = i === a.value; s.add(o); });
      s.onchange = () => send(a.plug, s.value);
      ctl.append(s);
    } else {
      const v = document.createElement('span');
      v.className = 'v';
      v.textContent = a.source ? `← ${a.source}` : fmt(a.value);
      ctl.append(v);
    }
    row.append(ctl);
    div.append(row);
  }
}

function numberControl(attr, value, onChange, slider, component) {
  const num = document.createElement('input');
  num.type = 'number';
  num.value = value;
  num.step = 'any';
  if (attr.min !== null) num.min = attr.min;
  if (attr.max !== null) num.max = attr.max;
  const plugId = attr.plug + (component === undefined ? '' : '#' + component);
  num.dataset.plug = plugId;
  const out = [];
  let r;
  if (slider) {
    r = document.createElement('input');
    r.type = 'range';
    const [lo, hi, step] = range(attr, value);
    r.min = lo; r.max = hi; r.step = attr.type === 'int' ? 1 : step; r.value = value;
    r.dataset.plug = plugId;
    r.oninput = () => { num.value = r.value; onChange(Number(r.value)); };
    out.push(r);
  }
  num.onchange = () => { if (r) r.value = num.value; onChange(Number(num.value)); };
  out.push(num);
  return out;
}

export function showEditStats(r) {
  const el = $('editStats');
  if (el) el.textContent = `edit: ${r.computes} computes, ${r.cutoffs} cut off, ${r.ms.toFixed(2)} ms (lazy graph)`;
}

/// Load errors and evaluation failures (failed computes, non-finite values) over the view;
/// statuses (an IK that cannot reach: the node still gave its best answer) on a line at
/// the bottom that does not hide the scene. Every problem also marks its node.
export function renderOverlay(loadErrors, problems) {
  const o = $('overlay');
  const parts = [];
  if (loadErrors && loadErrors.length) {
    parts.push('The rig failed to load; showing the last good scene.\n\n' + loadErrors.map((e) => e.text).join('\n\n'));
  }
  const failures = (problems || []).filter((p) => p.kind !== 'status');
  if (failures.length) {
    const label = { error: 'error', nonFinite: 'not finite' };
    parts.push('Evaluation problems:\n' + failures.map((p) => `${p.node} (${label[p.kind] || p.kind}): ${p.message}`).join('\n'));
  }
  o.hidden = parts.length === 0;
  o.textContent = parts.join('\n\n');
  const notes = (problems || []).filter((p) => p.kind === 'status');
  $('notes').hidden = notes.length === 0;
  $('notes').textContent = notes.map((p) => `${p.node}: ${p.message}`).join('\n');
}

export async function renderGraph(selected, onPick) {
  const div = $('graph');
  if (!selected) { div.innerHTML = '<p class="hint" style="padding:6px">Select a node to see the graph around it.</p>'; return; }
  const r = await fetch(`/api/graph?node=${encodeURIComponent(selected)}&depth=2`);
  div.innerHTML = r.ok ? await r.text() : '';
  div.querySelectorAll('[data-node]').forEach((g) => { g.onclick = () => onPick(g.dataset.node); });
  // Scroll the panel (only the panel) so the selected node is in the middle of it.
  const g = div.querySelector(`[data-node="${CSS.escape(selected)}"]`);
  if (g) {
    const box = g.getBoundingClientRect(), panel = div.getBoundingClientRect();
    div.scrollLeft += box.left + box.width / 2 - (panel.left + panel.width / 2);
    div.scrollTop += box.top + box.height / 2 - (panel.top + panel.height / 2);
  }
}

/// The profile table (from /api/profile): per node type and per node, sorted by total
/// time; costly nodes (at least half the costliest's share) highlighted; a node row
/// selects its node.
export function renderProfile(p, onPick) {
  const row = (r, costly, node) => `<tr class="${costly ? 'costly' : ''}"${node ? ` data-node="${esc(r.name)}"` : ''}>
    <td>${esc(r.name)}</td><td>${r.count}</td>
    <td>${r.totalUs.toFixed(1)}</td><td>${r.meanUs.toFixed(2)}</td><td>${(r.share * 100).toFixed(1)}%</td></tr>`;
  const head = '<tr><th>name</th><th>count</th><th>total µs</th><th>mean µs</th><th>share</th></tr>';
  const top = p.nodes.length ? p.nodes[0].share : 0;
  $('profileTable').innerHTML = `<p>${p.frames} frames, ${p.perFrameUs.toFixed(1)} µs of steps per frame</p>
    <h4>by node type</h4><table class="types">${head}${p.types.map((r) => row(r, false, false)).join('')}</table>
    <h4>by node</h4><table class="nodes">${head}${p.nodes.slice(0, 60).map((r) => row(r, r.share >= top * 0.5, true)).join('')}</table>`;
  $('profileTable').querySelectorAll('tr[data-node]').forEach((tr) => { tr.onclick = () => onPick(tr.dataset.node); });
}
