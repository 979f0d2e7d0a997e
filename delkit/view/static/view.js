// delkit view: draws what the server computed. No semantics here: truth values and accessible worlds come
// from the JSON API (api/eval, api/possible); the layout comes from delkit.drawing.draw (api/doc).
"use strict";

const state = { doc: null, frame: 0, views: {}, ready: false, lastEval: null, lastPossible: null, timings: {} };
window.delkitView = state;

function el(tag, attrs, text) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  return e;
}

async function api(path, body) {
  const opts = body === undefined ? {} : { method: "POST", headers: { "Content-Type": "application/json" },
                                           body: JSON.stringify(body) };
  const r = await fetch("api/" + path, opts);
  const data = await r.json();
  return { status: r.status, data };
}

const STYLE = [
  { selector: "node.world", style: {
      "shape": "ellipse", "width": "data(d)", "height": "data(d)", "background-color": "#f8f8f8",
      "border-width": 1.5, "border-color": "#222", "label": "data(label)", "text-wrap": "wrap",
      "text-valign": "center", "text-halign": "center", "font-size": 12, "min-zoomed-font-size": 6 } },
  { selector: "node.world.designated", style: { "border-width": 5, "border-style": "double" } },
  { selector: "node.world.holds", style: { "background-color": "#ffd54a" } },
  { selector: "node.world.fails", style: { "background-color": "#eeeeee", "color": "#777" } },
  { selector: "node.world.marked", style: { "background-color": "#b6e3b6" } },
  { selector: "node.world.from", style: { "border-color": "#000", "border-width": 4 } },
  { selector: "node.world.possible", style: { "underlay-color": "data(pc)", "underlay-opacity": 0.45,
                                               "underlay-padding": 8, "underlay-shape": "ellipse" } },
  { selector: "node.elabel", style: {
      "shape": "round-rectangle", "width": "data(w)", "height": 14, "background-color": "#fff",
      "background-opacity": 0.9, "border-width": 0, "label": "data(label)", "color": "data(color)",
      "font-size": 12, "text-valign": "center", "text-halign": "center", "events": "no",
      "min-zoomed-font-size": 6 } },
  { selector: "edge", style: {
      "width": 1.5, "line-color": "data(color)", "target-arrow-color": "data(color)", "curve-style": "straight",
      "arrow-scale": 0.9 } },
  { selector: "edge.oneway", style: { "target-arrow-shape": "triangle" } },
  { selector: "edge.bent", style: { "curve-style": "unbundled-bezier", "control-point-distances": "data(cpd)",
                                    "control-point-weights": 0.5 } },
  { selector: "edge.loop", style: { "curve-style": "bezier", "loop-direction": "0deg", "loop-sweep": "-50deg",
                                    "control-point-step-size": 40 } },
];

function elements(graph) {
  const els = [];
  const labels = graph.edges.length <= 600;   // delkit.drawing.draw places labels up to this size
  for (const n of graph.nodes) {
    els.push({ group: "nodes", classes: "world" + (n.designated ? " designated" : ""),
               data: { id: "n" + n.id, idx: n.id, label: n.lines.join("\n"), d: 2 * n.r, name: n.name,
                       props: n.props || null, designated: n.designated, pc: "#888" },
               position: { x: n.x, y: n.y } });
  }
  graph.edges.forEach((e, i) => {
    const a = graph.nodes[e.u], b = graph.nodes[e.v];
    const dist = Math.hypot(b.x - a.x, b.y - a.y) || 1;
    const classes = [e.both ? "both" : "oneway"];
    if (e.u === e.v) classes.push("loop");
    else if (e.bend) classes.push("bent");
    const item = { group: "edges", classes: classes.join(" "),
                   data: { id: "e" + i, source: "n" + e.u, target: "n" + e.v, color: e.color, agents: e.agents,
                           both: e.both, cpd: -e.bend * dist * 0.125 } };
    if (e.u === e.v) item.style = { "loop-direction": e.loop + "deg" };
    els.push(item);
    if (labels) {
      const text = e.agents.join(",");
      els.push({ group: "nodes", classes: "elabel", selectable: false, grabbable: false,
                 data: { id: "l" + i, label: text, color: e.color, w: 7 * text.length + 6 },
                 position: { x: e.lx, y: e.ly } });
    }
  });
  return els;
}

// One view per panel: cytoscape.js for graphs below BIG worlds; a plain canvas above (cytoscape needs seconds
// to build ~7,000 elements on a loaded 2-core machine; the canvas draws them in milliseconds).
const BIG = 300;

class CyView {
  constructor(container, graph, onTap) {
    this.graph = graph;
    this.cy = cytoscape({ container, elements: elements(graph), style: STYLE, layout: { name: "preset" },
                          maxZoom: 3, motionBlur: false });
    this.cy.on("tap", "node.world", (ev) => onTap(ev.target.data("idx")));
  }
  fit() {
    this.cy.resize();
    this.cy.fit(undefined, 16);
    if (this.cy.zoom() > 1.2) { this.cy.zoom(1.2); this.cy.center(); }
  }
  worlds() { return this.cy.nodes("node.world"); }
  setTruth(truth) {
    this.cy.batch(() => this.worlds().forEach((n) => {
      n.removeClass("holds fails marked");
      if (truth) n.addClass(truth[n.data("idx")] ? "holds" : "fails");
    }));
  }
  setMarked(set) {
    this.cy.batch(() => this.worlds().forEach((n) => {
      n.removeClass("holds fails marked");
      if (set.has(n.data("idx"))) n.addClass("marked");
    }));
  }
  setPossible(set, color, from) {
    this.cy.batch(() => this.worlds().forEach((n) => {
      n.removeClass("possible from");
      if (set.has(n.data("idx"))) { n.data("pc", color); n.addClass("possible"); }
      if (n.data("idx") === from) n.addClass("from");
    }));
  }
  highlighted() { return this.cy.nodes("node.world.holds").map((n) => n.data("name")); }
  drawnEdges() {
    return this.cy.edges().map((e) => ({ u: e.source().data("idx"), v: e.target().data("idx"),
                                         agents: e.data("agents"), both: e.data("both") }));
  }
  destroy() { this.cy.destroy(); }
}

class CanvasView {
  constructor(container, graph, onTap) {
    this.graph = graph;
    this.truth = null; this.marked = new Set(); this.possible = new Set(); this.pcolor = "#888"; this.from = -1;
    this.canvas = document.createElement("canvas");
    this.canvas.className = "big-graph";
    container.appendChild(this.canvas);
    this.canvas.addEventListener("click", (ev) => {
      const r = this.canvas.getBoundingClientRect();
      const k = this.nearest(ev.clientX - r.left, ev.clientY - r.top);
      if (k >= 0) onTap(k);
    });
    let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
    for (const n of graph.nodes) {
      x0 = Math.min(x0, n.x - n.r); y0 = Math.min(y0, n.y - n.r);
      x1 = Math.max(x1, n.x + n.r); y1 = Math.max(y1, n.y + n.r);
    }
    this.box = [x0, y0, x1, y1];
  }
  fit() {
    const w = this.canvas.parentElement.clientWidth, h = this.canvas.parentElement.clientHeight;
    this.canvas.width = w; this.canvas.height = h;
    const [x0, y0, x1, y1] = this.box;
    this.s = Math.min((w - 24) / Math.max(x1 - x0, 1), (h - 24) / Math.max(y1 - y0, 1), 1.2);
    this.ox = (w - (x1 - x0) * this.s) / 2 - x0 * this.s;
    this.oy = (h - (y1 - y0) * this.s) / 2 - y0 * this.s;
    this.draw();
  }
  px(n) { return [n.x * this.s + this.ox, n.y * this.s + this.oy]; }
  radius(n) { return Math.max(3, n.r * this.s); }
  nearest(x, y) {
    let best = -1, bd = Infinity;
    this.graph.nodes.forEach((n, i) => {
      const [a, b] = this.px(n);
      const d = Math.hypot(a - x, b - y);
      if (d < bd && d <= this.radius(n) + 3) { bd = d; best = i; }
    });
    return best;
  }
  draw() {
    const ctx = this.canvas.getContext("2d");
    const g = this.graph, nodes = g.nodes;
    ctx.clearRect(0, 0, this.canvas.width, this.canvas.height);
    const byColor = {};
    for (const e of g.edges) if (e.u !== e.v) (byColor[e.color] = byColor[e.color] || []).push(e);
    ctx.globalAlpha = 0.35;
    ctx.lineWidth = 1;
    for (const [color, es] of Object.entries(byColor)) {
      ctx.strokeStyle = color;
      ctx.beginPath();
      for (const e of es) {
        const [a, b] = this.px(nodes[e.u]), [c, d] = this.px(nodes[e.v]);
        ctx.moveTo(a, b); ctx.lineTo(c, d);
      }
      ctx.stroke();
    }
    ctx.globalAlpha = 1;
    nodes.forEach((n, i) => {
      const [x, y] = this.px(n), r = this.radius(n);
      if (this.possible.has(i)) {
        ctx.fillStyle = this.pcolor; ctx.globalAlpha = 0.45;
        ctx.beginPath(); ctx.arc(x, y, r + 4, 0, 2 * Math.PI); ctx.fill(); ctx.globalAlpha = 1;
      }
      ctx.fillStyle = this.truth ? (this.truth[i] ? "#ffd54a" : "#eeeeee") : (this.marked.has(i) ? "#b6e3b6" : "#f8f8f8");
      ctx.strokeStyle = "#222";
      ctx.lineWidth = (n.designated ? 2.5 : 0.8) + (i === this.from ? 2 : 0);
      ctx.beginPath(); ctx.arc(x, y, r, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
    });
  }
  setTruth(truth) { this.truth = truth; this.marked = new Set(); this.draw(); }
  setMarked(set) { this.truth = null; this.marked = set; this.draw(); }
  setPossible(set, color, from) { this.possible = set; this.pcolor = color; this.from = from; this.draw(); }
  highlighted() {
    return this.truth ? this.graph.nodes.filter((n, i) => this.truth[i]).map((n) => n.name) : [];
  }
  drawnEdges() { return this.graph.edges.map((e) => ({ u: e.u, v: e.v, agents: e.agents, both: e.both })); }
  destroy() { this.canvas.remove(); }
}

function renderFrame(k) {
  const doc = state.doc;
  state.frame = k;
  const fr = doc.frames[k];
  document.getElementById("frame-select").value = String(k);
  document.getElementById("frame-title").textContent = fr.title;
  // a frame without graphs (an e-PICO mission step): its table and picture take the whole width
  document.querySelector("main").classList.toggle("no-graphs", fr.panels.length === 0);
  const panels = document.getElementById("panels");
  for (const v of Object.values(state.views)) v.destroy();
  state.views = {};
  panels.replaceChildren();
  const evalSel = document.getElementById("eval-panel");
  const previous = evalSel.value;
  evalSel.replaceChildren();
  const agents = new Set();
  const colors = {};
  for (const p of fr.panels) {
    const box = el("div", { class: "panel", id: "panel-" + p.key });
    box.appendChild(el("h2", {}, p.title));
    const names = Object.keys(p.marks || {});
    if (names.length) {
      const marks = el("div", { class: "marks" });
      for (const m of names) {
        const b = el("button", { "data-mark": m }, m);
        b.addEventListener("click", () => showMark(p.key, m));
        marks.appendChild(b);
      }
      box.appendChild(marks);
    }
    const g = el("div", { class: "graph", id: "graph-" + p.key });
    box.appendChild(g);
    box.appendChild(el("div", { class: "caption" }, p.graph.caption.join("; ")));
    panels.appendChild(box);
    const View = p.graph.nodes.length >= BIG ? CanvasView : CyView;
    state.views[p.key] = new View(g, p.graph, (idx) => askPossible(p.key, idx));
    if (p.kripke) evalSel.appendChild(el("option", { value: p.key }, p.title));
    for (const a of p.graph.agents) { agents.add(a); colors[a] = p.graph.colors[a]; }
  }
  // fit once the panels have their final size (flex layout)
  for (const v of Object.values(state.views)) v.fit();
  const carried = fr.data && fr.data.carried;
  if ([...evalSel.options].some((o) => o.value === previous)) evalSel.value = previous;
  else if (carried && [...evalSel.options].some((o) => o.value === carried)) evalSel.value = carried;
  document.getElementById("formula-box").hidden = evalSel.options.length === 0;
  const agentSel = document.getElementById("agent");
  const chosen = agentSel.value;
  agentSel.replaceChildren(...[...agents].map((a) => el("option", { value: a }, a)));
  if (agents.has(chosen)) agentSel.value = chosen;
  document.getElementById("agent-box").hidden = agents.size === 0;
  document.getElementById("legend").replaceChildren(...[...agents].map((a) => {
    const s = el("span", {}, "— " + a); s.style.color = colors[a]; return s; }));
  const notes = document.getElementById("frame-notes");
  notes.replaceChildren(...fr.notes.map((t) => el("li", {}, t)));
  document.getElementById("frame-notes-box").hidden = fr.notes.length === 0;
  const table = document.getElementById("frame-table");
  table.replaceChildren();
  if (fr.table) {
    fr.table.forEach((row, i) => {
      const tr = el("tr");
      for (const c of row) tr.appendChild(el(i === 0 ? "th" : "td", {}, c));
      table.appendChild(tr);
    });
  }
  document.getElementById("table-box").hidden = !fr.table;
  const img = document.getElementById("frame-image");
  if (fr.image) img.src = "api/image/" + k; else img.removeAttribute("src");
  document.getElementById("image-box").hidden = !fr.image;
  document.getElementById("formula-result").replaceChildren();
  document.getElementById("possible-result").replaceChildren(el("small", {}, "click a world"));
  const f = document.getElementById("formula").value.trim();
  if (f) return evaluate(f);
  return Promise.resolve(null);
}

function showMark(key, mark) {
  const p = state.doc.frames[state.frame].panels.find((q) => q.key === key);
  state.views[key].setMarked(new Set(p.marks[mark]));
}

async function evaluate(text) {
  const key = document.getElementById("eval-panel").value;
  const errBox = document.getElementById("formula-error");
  const res = document.getElementById("formula-result");
  const t0 = performance.now();
  const { status, data } = await api("eval", { frame: state.frame, panel: key, formula: text });
  const view = state.views[key];
  state.lastEval = data;
  if (status !== 200 || !data.ok) {
    let msg = data.error || ("error " + status);
    if (data.column) msg += "\n" + text + "\n" + " ".repeat(Math.max(0, data.column - 1)) + "^";
    errBox.textContent = msg;
    errBox.hidden = false;
    res.replaceChildren();
    if (view) view.setTruth(null);
    state.timings.eval = performance.now() - t0;
    return data;
  }
  errBox.hidden = true;
  view.setTruth(data.truth);
  const holds = el("span", { class: data.holds ? "yes" : "no" }, data.holds ? "holds" : "does not hold");
  const shown = data.worlds.length > 40 ? data.worlds.slice(0, 40).join(", ") + ", …" : data.worlds.join(", ");
  res.replaceChildren(el("div", {}, data.formula + ": "), holds,
                      el("span", {}, " at the designated world(s); true in " + data.worlds.length + " of " +
                                     data.truth.length + " world(s) (highlighted)" + (shown ? ": " + shown : "")));
  state.timings.eval = performance.now() - t0;
  return data;
}

async function askPossible(key, world) {
  const agent = document.getElementById("agent").value;
  const { status, data } = await api("possible", { frame: state.frame, panel: key, agent, world });
  const out = document.getElementById("possible-result");
  state.lastPossible = data;
  if (status !== 200 || !data.ok) { out.textContent = data.error; return data; }
  const color = state.doc.frames[state.frame].panels.find((q) => q.key === key).graph.colors[agent];
  state.views[key].setPossible(new Set(data.worlds), color, world);
  out.textContent = `at ${data.name}, ${agent} considers possible: ${data.names.join(", ") || "nothing (believes ⊥)"}`;
  return data;
}

// for tests and scripts: what the page draws, read back from the graph
state.highlighted = (key) => state.views[key].highlighted();
state.drawn = (key) => {
  const p = state.doc.frames[state.frame].panels.find((q) => q.key === key);
  const worlds = p.graph.nodes.map((n) => ({ idx: n.id, name: n.name, props: n.props || null,
                                             designated: n.designated }));
  return { worlds, edges: state.views[key].drawnEdges(), s5: p.graph.s5, agents: p.graph.agents };
};
state.evaluate = evaluate;
state.possible = askPossible;
state.show = renderFrame;

async function main() {
  const t0 = performance.now();
  const { status, data } = await api("doc");
  if (status !== 200) { document.body.textContent = data.error; return; }
  state.doc = data;
  state.timings.fetch = performance.now() - t0;
  document.getElementById("sources").textContent = data.sources.join("  ");
  document.getElementById("doc-notes").replaceChildren(...data.notes.map((t) => el("li", {}, t)));
  const sel = document.getElementById("frame-select");
  data.frames.forEach((f, i) => sel.appendChild(el("option", { value: String(i) }, f.title)));
  document.getElementById("stepper").hidden = data.frames.length < 2;
  sel.addEventListener("change", () => renderFrame(Number(sel.value)));
  document.getElementById("prev").addEventListener("click", () => { if (state.frame > 0) renderFrame(state.frame - 1); });
  document.getElementById("next").addEventListener("click", () => {
    if (state.frame < data.frames.length - 1) renderFrame(state.frame + 1); });
  document.addEventListener("keydown", (ev) => {
    if (ev.target.tagName === "INPUT") return;
    if (ev.key === "ArrowLeft" && state.frame > 0) renderFrame(state.frame - 1);
    if (ev.key === "ArrowRight" && state.frame < data.frames.length - 1) renderFrame(state.frame + 1);
  });
  const input = document.getElementById("formula");
  document.getElementById("eval").addEventListener("click", () => evaluate(input.value));
  input.addEventListener("keydown", (ev) => { if (ev.key === "Enter") evaluate(input.value); });
  await renderFrame(0);
  state.timings.ready = performance.now();
  state.ready = true;
}

main();
