// delkit view: draws what the server computed. No semantics here: truth values and accessible worlds come
// from the JSON API (api/eval, api/possible); the layout comes from delkit.draw (api/doc).
"use strict";

const state = { doc: null, frame: 0, cys: {}, ready: false, lastEval: null, lastPossible: null, timings: {} };
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
  const labels = graph.edges.length <= 600;   // delkit.draw places labels up to this size
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

function renderFrame(k) {
  const doc = state.doc;
  state.frame = k;
  const fr = doc.frames[k];
  document.getElementById("frame-select").value = String(k);
  document.getElementById("frame-title").textContent = fr.title;
  const panels = document.getElementById("panels");
  for (const cy of Object.values(state.cys)) cy.destroy();
  state.cys = {};
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
    const cy = cytoscape({ container: g, elements: elements(p.graph), style: STYLE, layout: { name: "preset" },
                           maxZoom: 3, textureOnViewport: p.graph.nodes.length > 300,
                           hideEdgesOnViewport: p.graph.nodes.length > 300 });
    cy.on("tap", "node.world", (ev) => askPossible(p.key, ev.target.data("idx")));
    state.cys[p.key] = cy;
    if (p.kripke) evalSel.appendChild(el("option", { value: p.key }, p.title));
    for (const a of p.graph.agents) { agents.add(a); colors[a] = p.graph.colors[a]; }
  }
  // fit once the panels have their final size (flex layout)
  for (const cy of Object.values(state.cys)) fitGraph(cy);
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

function fitGraph(cy) {
  cy.resize();
  cy.fit(undefined, 16);
  if (cy.zoom() > 1.2) { cy.zoom(1.2); cy.center(); }
}

function clearClasses(cy, names) {
  cy.nodes("node.world").removeClass(names);
}

function showMark(key, mark) {
  const cy = state.cys[key];
  const p = state.doc.frames[state.frame].panels.find((q) => q.key === key);
  clearClasses(cy, "holds fails marked");
  const set = new Set(p.marks[mark]);
  cy.nodes("node.world").forEach((n) => { if (set.has(n.data("idx"))) n.addClass("marked"); });
}

async function evaluate(text) {
  const key = document.getElementById("eval-panel").value;
  const errBox = document.getElementById("formula-error");
  const res = document.getElementById("formula-result");
  const t0 = performance.now();
  const { status, data } = await api("eval", { frame: state.frame, panel: key, formula: text });
  const cy = state.cys[key];
  state.lastEval = data;
  if (status !== 200 || !data.ok) {
    let msg = data.error || ("error " + status);
    if (data.column) msg += "\n" + text + "\n" + " ".repeat(Math.max(0, data.column - 1)) + "^";
    errBox.textContent = msg;
    errBox.hidden = false;
    res.replaceChildren();
    if (cy) clearClasses(cy, "holds fails marked");
    state.timings.eval = performance.now() - t0;
    return data;
  }
  errBox.hidden = true;
  clearClasses(cy, "holds fails marked");
  cy.batch(() => {
    cy.nodes("node.world").forEach((n) => n.addClass(data.truth[n.data("idx")] ? "holds" : "fails"));
  });
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
  const cy = state.cys[key];
  cy.nodes("node.world").removeClass("possible from");
  const color = state.doc.frames[state.frame].panels.find((q) => q.key === key).graph.colors[agent];
  const set = new Set(data.worlds);
  cy.nodes("node.world").forEach((n) => {
    if (set.has(n.data("idx"))) { n.data("pc", color); n.addClass("possible"); }
    if (n.data("idx") === world) n.addClass("from");
  });
  out.textContent = `at ${data.name}, ${agent} considers possible: ${data.names.join(", ") || "nothing (believes ⊥)"}`;
  return data;
}

// for tests and scripts: what the page draws, read back from the graph
state.highlighted = (key) => state.cys[key].nodes("node.world.holds").map((n) => n.data("name"));
state.drawn = (key) => {
  const cy = state.cys[key];
  const worlds = cy.nodes("node.world").map((n) => ({ idx: n.data("idx"), name: n.data("name"),
                                                       props: n.data("props"), designated: n.data("designated") }));
  const edges = cy.edges().map((e) => ({ u: e.source().data("idx"), v: e.target().data("idx"),
                                         agents: e.data("agents"), both: e.data("both") }));
  const p = state.doc.frames[state.frame].panels.find((q) => q.key === key);
  return { worlds, edges, s5: p.graph.s5 };
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
