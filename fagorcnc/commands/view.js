// fagorcnc view: the tool path beside the program text, in one page with no server and no network.
// Written for fagorcnc (MIT, like the package).  The data is the JSON in <script id="fagorcnc-data">.
"use strict";
(function () {
  const data = JSON.parse(document.getElementById("fagorcnc-data").textContent);
  const canvas = document.getElementById("path");
  const ctx = canvas.getContext("2d");
  const text = document.getElementById("text");
  const slider = document.getElementById("time");
  const clockOut = document.getElementById("clock");
  const colourBy = document.getElementById("colour");
  const segs = data.segments;
  const palette = ["#1f77b4", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"];
  let yaw = -0.6, pitch = 0.9, zoom = 1, panX = 0, panY = 0;
  let selected = null;          // the source line selected
  let now = data.cycle_time;    // the time shown (s)
  const centre = [0, 1, 2].map(k => (data.bounds.min[k] + data.bounds.max[k]) / 2);
  const size = Math.max(1e-6, ...[0, 1, 2].map(k => data.bounds.max[k] - data.bounds.min[k]));

  // ---- the program text
  const lineEls = new Map();
  data.lines.forEach((src, i) => {
    const el = document.createElement("div");
    el.className = "line";
    el.dataset.line = String(i + 1);
    if (data.failing && data.failing.line === i + 1) el.classList.add("failing");
    el.innerHTML = "<span class=no>" + (i + 1) + "</span>";
    el.appendChild(document.createTextNode(src || " "));
    el.addEventListener("click", () => select(i + 1, false));
    text.appendChild(el);
    lineEls.set(i + 1, el);
  });

  // ---- projection: orthographic, yaw about Z then pitch about the screen's horizontal axis
  function project(p) {
    const x = p[0] - centre[0], y = p[1] - centre[1], z = p[2] - centre[2];
    const cy = Math.cos(yaw), sy = Math.sin(yaw), cp = Math.cos(pitch), sp = Math.sin(pitch);
    const x1 = cy * x - sy * y, y1 = sy * x + cy * y;
    const up = cp * y1 + sp * z;     // pitch 0: seen from above (XY), pi/2: from the front (XZ)
    const scale = zoom * 0.85 * Math.min(canvas.width, canvas.height) / size;
    return [canvas.width / 2 + panX + x1 * scale, canvas.height / 2 + panY - up * scale];
  }

  function colour(s) {
    if (selected !== null && s.line === selected && s.file === data.file) return "#ffb000";
    if (colourBy.value === "tool") return palette[s.tool % palette.length];
    if (colourBy.value === "feed") {
      if (s.rapid) return "#d62728";
      const f = Math.min(1, s.feed / (data.max_feed || 1));
      return "hsl(" + Math.round(220 - 180 * f) + ",80%,40%)";
    }
    return s.rapid ? "#d62728" : "#1f77b4";
  }

  function box() {
    const lo = data.limits && data.limits.min, hi = data.limits && data.limits.max;
    if (!lo) return;
    const c = [];
    for (let i = 0; i < 8; i++) c.push(project([i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]]));
    ctx.strokeStyle = "#999"; ctx.setLineDash([2, 4]); ctx.lineWidth = 1;
    for (const [a, b] of [[0,1],[2,3],[4,5],[6,7],[0,2],[1,3],[4,6],[5,7],[0,4],[1,5],[2,6],[3,7]]) {
      ctx.beginPath(); ctx.moveTo(c[a][0], c[a][1]); ctx.lineTo(c[b][0], c[b][1]); ctx.stroke();
    }
    ctx.setLineDash([]);
  }

  function draw() {
    ctx.clearRect(0, 0, canvas.width, canvas.height);
    box();
    let tool = null;
    for (const s of segs) {
      if (s.t0 > now || (s.t0 === now && s.duration > 0 && now < data.cycle_time)) break;   // not reached yet
      const pts = s.points;
      const frac = s.duration > 0 ? Math.min(1, (now - s.t0) / s.duration) : 1;
      const last = Math.max(1, Math.ceil(frac * (pts.length - 1)));
      ctx.strokeStyle = colour(s);
      ctx.lineWidth = selected !== null && s.line === selected && s.file === data.file ? 3 : 1.2;
      ctx.setLineDash(s.rapid ? [5, 4] : []);
      ctx.beginPath();
      let p = project(pts[0]);
      ctx.moveTo(p[0], p[1]);
      for (let k = 1; k <= last; k++) { p = project(pts[k]); ctx.lineTo(p[0], p[1]); }
      ctx.stroke();
      tool = p;
    }
    ctx.setLineDash([]);
    if (data.failing && data.failing.point) {
      const f = project(data.failing.point);
      ctx.strokeStyle = "#e00000"; ctx.lineWidth = 2;
      ctx.beginPath(); ctx.arc(f[0], f[1], 8, 0, 2 * Math.PI); ctx.stroke();
    }
    if (tool && now < data.cycle_time) {
      ctx.fillStyle = "#000"; ctx.beginPath(); ctx.arc(tool[0], tool[1], 4, 0, 2 * Math.PI); ctx.fill();
    }
    clockOut.textContent = now.toFixed(2) + " s / " + data.cycle_time.toFixed(2) + " s";
  }

  // ---- selection: a segment picks its line, a line its segments
  function select(line, scroll) {
    if (selected !== null && lineEls.has(selected)) lineEls.get(selected).classList.remove("hl");
    selected = line;
    const el = lineEls.get(line);
    if (el) { el.classList.add("hl"); if (scroll) el.scrollIntoView({block: "center"}); }
    document.getElementById("selected").textContent = line === null ? "" : "line " + line;
    draw();
  }

  function distance(px, py, a, b) {
    const dx = b[0] - a[0], dy = b[1] - a[1], den = dx * dx + dy * dy;
    const t = den > 0 ? Math.max(0, Math.min(1, ((px - a[0]) * dx + (py - a[1]) * dy) / den)) : 0;
    return Math.hypot(px - a[0] - t * dx, py - a[1] - t * dy);
  }

  function pick(px, py) {
    let best = 8, found = null;
    for (const s of segs) {
      if (s.t0 > now) break;
      let a = project(s.points[0]);
      for (let k = 1; k < s.points.length; k++) {
        const b = project(s.points[k]);
        const d = distance(px, py, a, b);
        if (d < best) { best = d; found = s; }
        a = b;
      }
    }
    return found;
  }

  let drag = null;
  canvas.addEventListener("mousedown", e => { drag = {x: e.offsetX, y: e.offsetY, moved: false, pan: e.shiftKey}; });
  canvas.addEventListener("mousemove", e => {
    if (!drag) return;
    const dx = e.offsetX - drag.x, dy = e.offsetY - drag.y;
    if (Math.abs(dx) + Math.abs(dy) > 2) drag.moved = true;
    if (!drag.moved) return;
    if (drag.pan) { panX += dx; panY += dy; } else { yaw += dx * 0.01; pitch = Math.max(0, Math.min(Math.PI, pitch + dy * 0.01)); }
    drag.x = e.offsetX; drag.y = e.offsetY; draw();
  });
  canvas.addEventListener("mouseup", e => {
    if (drag && !drag.moved) {
      const s = pick(e.offsetX, e.offsetY);
      if (s) select(s.file === data.file ? s.line : null, true);
    }
    drag = null;
  });
  canvas.addEventListener("wheel", e => { e.preventDefault(); zoom *= e.deltaY < 0 ? 1.15 : 1 / 1.15; draw(); });
  slider.max = String(data.cycle_time);
  slider.step = String(Math.max(data.cycle_time / 2000, 1e-3));
  slider.value = String(data.cycle_time);
  slider.addEventListener("input", () => { now = Number(slider.value); draw(); });
  colourBy.addEventListener("change", draw);
  let timer = null;
  document.getElementById("play").addEventListener("click", () => {
    if (timer) { clearInterval(timer); timer = null; return; }
    if (now >= data.cycle_time) now = 0;
    const start = performance.now() - now * 1000 / Number(document.getElementById("speed").value);
    timer = setInterval(() => {
      now = Math.min(data.cycle_time, (performance.now() - start) / 1000 * Number(document.getElementById("speed").value));
      slider.value = String(now); draw();
      if (now >= data.cycle_time) { clearInterval(timer); timer = null; }
    }, 40);
  });
  document.getElementById("reset").addEventListener("click", () => { yaw = -0.6; pitch = 0.9; zoom = 1; panX = panY = 0; draw(); });
  function resize() { canvas.width = canvas.clientWidth; canvas.height = canvas.clientHeight; draw(); }
  window.addEventListener("resize", resize);
  resize();
  if (data.failing) select(data.failing.line, true);

  // what the page's test (and a curious user's console) may ask
  window.fagorcncView = {
    screenPoint(i) { const s = segs[i]; const k = Math.floor((s.points.length - 1) / 2);
      const a = project(s.points[k]), b = project(s.points[k + 1] || s.points[k]);
      const r = canvas.getBoundingClientRect();
      return [r.left + (a[0] + b[0]) / 2, r.top + (a[1] + b[1]) / 2]; },
    selectedLine() { return selected; },
    setTime(t) { now = t; slider.value = String(t); draw(); },
    segments: segs.length,
  };
})();
