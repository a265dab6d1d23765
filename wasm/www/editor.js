// The canvas editor: draw segments and polygons, select, move, rotate and scale objects,
// snap to a grid and to vertices, undo, delete. It edits the model of model.js and calls
// `onChange()` after every edit; it draws patches in the colours it is given.
import {
  bounds, cloneModel, flipObject, inside, mapObject, points, signedArea2, surface,
} from './model.js';

const HANDLE = 7; // handle half-size, CSS pixels
const PICK = 8; // how close a click must be to a surface to select it, CSS pixels
const FRONT = 2.5; // patches are drawn this many pixels in front of their surface
const UNDO_DEPTH = 200;

export class Editor {
  constructor(canvas, { onChange, onStatus }) {
    this.canvas = canvas;
    this.g = canvas.getContext('2d');
    this.onChange = onChange;
    this.onStatus = onStatus;
    this.model = { objects: [] };
    this.undoStack = [];
    this.tool = 'select';
    this.snap = true;
    this.density = 10; // patches per unit length for new surfaces
    this.twoSided = true; // new segments are walls seen from both sides
    this.selected = -1;
    this.draft = []; // vertices of the segment or polygon being drawn
    this.hover = null; // pointer position in scene coordinates
    this.drag = null;
    this.colours = null; // per-patch CSS colours, or null
    this.view = { cx: 0, cy: 0, scale: 100 };
    new ResizeObserver(() => this.resize()).observe(canvas);
    canvas.addEventListener('pointerdown', (e) => this.pointerDown(e));
    canvas.addEventListener('pointermove', (e) => this.pointerMove(e));
    canvas.addEventListener('pointerup', (e) => this.pointerUp(e));
    canvas.addEventListener('dblclick', (e) => this.doubleClick(e));
    canvas.addEventListener('pointerleave', () => {
      this.hover = null;
      this.draw();
    });
    // Keys act on the editor unless the user is typing in a form field.
    window.addEventListener('keydown', (e) => {
      if (!['INPUT', 'SELECT', 'TEXTAREA'].includes(e.target?.tagName)) this.key(e);
    });
    canvas.tabIndex = 0;
    this.resize();
  }

  // ---- model ------------------------------------------------------------------------------

  /// Replaces the whole model (a preset, an import, a link) and fits the view.
  setModel(model, { undoable = true } = {}) {
    if (undoable) this.pushUndo();
    this.model = model;
    this.selected = -1;
    this.draft = [];
    this.fit();
    this.onChange('geometry');
  }

  pushUndo() {
    this.undoStack.push(cloneModel(this.model));
    if (this.undoStack.length > UNDO_DEPTH) this.undoStack.shift();
  }

  undo() {
    if (this.draft.length) {
      this.draft = [];
      this.draw();
      return;
    }
    const previous = this.undoStack.pop();
    if (!previous) return;
    this.model = previous;
    this.selected = -1;
    this.onChange('geometry');
  }

  deleteSelected() {
    if (this.selected < 0) return;
    this.pushUndo();
    this.model.objects.splice(this.selected, 1);
    this.selected = -1;
    this.onChange('geometry');
  }

  flipSelected() {
    if (this.selected < 0) return;
    this.pushUndo();
    flipObject(this.model.objects[this.selected]);
    this.onChange('geometry');
  }

  /// Rotates (radians) and scales the selected object about its centre.
  transformSelected(angle, factor) {
    if (this.selected < 0) return;
    this.pushUndo();
    const object = this.model.objects[this.selected];
    const [x0, y0, x1, y1] = bounds(points(object));
    const [cx, cy] = [(x0 + x1) / 2, (y0 + y1) / 2];
    const [c, s] = [Math.cos(angle) * factor, Math.sin(angle) * factor];
    mapObject(object, ([x, y]) => [cx + c * (x - cx) - s * (y - cy), cy + s * (x - cx) + c * (y - cy)]);
    this.onChange('geometry');
  }

  setTool(tool) {
    this.tool = tool;
    this.draft = [];
    this.canvas.style.cursor = tool === 'select' ? 'default' : 'crosshair';
    this.status();
    this.draw();
  }

  // ---- view -------------------------------------------------------------------------------

  resize() {
    const r = this.canvas.getBoundingClientRect();
    const dpr = window.devicePixelRatio || 1;
    this.canvas.width = Math.max(1, Math.round(r.width * dpr));
    this.canvas.height = Math.max(1, Math.round(r.height * dpr));
    this.dpr = dpr;
    this.cssWidth = r.width;
    this.cssHeight = r.height;
    if (!this.fitted) this.fit();
    this.draw();
  }

  /// Centres the scene with a margin (or the square [-1, 1]² when empty).
  fit() {
    const pts = this.model.objects.flatMap(points);
    const [x0, y0, x1, y1] = pts.length ? bounds(pts) : [-1, -1, 1, 1];
    const w = Math.max(x1 - x0, 1e-9);
    const h = Math.max(y1 - y0, 1e-9);
    const margin = 28;
    const scale = Math.min((this.cssWidth - 2 * margin) / w, (this.cssHeight - 2 * margin) / h);
    this.view = { cx: (x0 + x1) / 2, cy: (y0 + y1) / 2, scale: scale > 0 ? scale : 100 };
    this.fitted = this.cssWidth > 0;
    this.draw();
  }

  toScreen([x, y]) {
    const v = this.view;
    return [this.cssWidth / 2 + (x - v.cx) * v.scale, this.cssHeight / 2 - (y - v.cy) * v.scale];
  }

  toScene(e) {
    const r = this.canvas.getBoundingClientRect();
    const [sx, sy] = [e.clientX - r.left, e.clientY - r.top];
    const v = this.view;
    return [v.cx + (sx - this.cssWidth / 2) / v.scale, v.cy - (sy - this.cssHeight / 2) / v.scale];
  }

  /// A round grid step of about 20 pixels.
  gridStep() {
    const raw = 20 / this.view.scale;
    const p = 10 ** Math.floor(Math.log10(raw));
    return [1, 2, 5, 10].map((m) => m * p).find((s) => s >= raw);
  }

  /// Snaps p to a nearby vertex (within PICK pixels), else to the grid (when snapping).
  snapPoint(p) {
    if (!this.snap) return p;
    let best = null;
    let bestD = PICK / this.view.scale;
    for (const q of [...this.model.objects.flatMap(points), ...this.draft]) {
      const d = Math.hypot(q[0] - p[0], q[1] - p[1]);
      if (d < bestD) [best, bestD] = [q, d];
    }
    if (best) return [...best];
    const s = this.gridStep();
    // Round to the grid, then to 12 significant digits so 0.1 + 0.2 stays 0.3 in the file.
    return p.map((x) => Number((Math.round(x / s) * s).toPrecision(12)));
  }

  // ---- pointer and keys ---------------------------------------------------------------------

  pointerDown(e) {
    this.canvas.focus();
    this.canvas.setPointerCapture(e.pointerId);
    const p = this.toScene(e);
    if (this.tool === 'segment' || this.tool === 'polygon') {
      const q = this.snapPoint(p);
      if (this.tool === 'segment') {
        if (this.draft.length === 0) this.draft = [q];
        else this.finishSegment(q);
      } else {
        const first = this.draft[0];
        if (first && this.draft.length >= 3 && this.pixels(first, q) < PICK) this.finishPolygon();
        else this.draft.push(q);
      }
      this.draw();
      return;
    }
    // Select tool: a handle of the selection, else the nearest object.
    const handle = this.handleAt(p);
    if (handle) {
      this.pushUndo();
      this.drag = { kind: handle, start: p, original: cloneModel(this.model), moved: false };
      return;
    }
    this.selected = this.objectAt(p);
    if (this.selected >= 0) {
      this.pushUndo();
      this.drag = { kind: 'move', start: this.snapPoint(p), original: cloneModel(this.model), moved: false };
    }
    this.status();
    this.draw();
  }

  pointerMove(e) {
    const p = this.toScene(e);
    this.hover = this.tool === 'select' ? p : this.snapPoint(p);
    const d = this.drag;
    if (d) {
      const object = this.model.objects[this.selected];
      const original = d.original.objects[this.selected];
      object.surfaces = cloneModel({ objects: [original] }).objects[0].surfaces;
      const [x0, y0, x1, y1] = bounds(points(original));
      const [cx, cy] = [(x0 + x1) / 2, (y0 + y1) / 2];
      if (d.kind === 'move') {
        const q = this.snapPoint(p);
        const [dx, dy] = [q[0] - d.start[0], q[1] - d.start[1]];
        mapObject(object, ([x, y]) => [x + dx, y + dy]);
      } else if (d.kind === 'rotate') {
        let a = Math.atan2(p[1] - cy, p[0] - cx) - Math.atan2(d.start[1] - cy, d.start[0] - cx);
        if (this.snap) a = Math.round(a / (Math.PI / 24)) * (Math.PI / 24); // 7.5° steps
        const [c, s] = [Math.cos(a), Math.sin(a)];
        mapObject(object, ([x, y]) => [cx + c * (x - cx) - s * (y - cy), cy + s * (x - cx) + c * (y - cy)]);
      } else {
        let f = Math.hypot(p[0] - cx, p[1] - cy) / Math.max(Math.hypot(d.start[0] - cx, d.start[1] - cy), 1e-12);
        if (this.snap) f = Math.max(0.05, Math.round(f * 20) / 20);
        mapObject(object, ([x, y]) => [cx + f * (x - cx), cy + f * (y - cy)]);
      }
      d.moved = true;
    }
    this.draw();
  }

  pointerUp(e) {
    const d = this.drag;
    this.drag = null;
    if (d) {
      if (d.moved) this.onChange('geometry');
      else this.undoStack.pop(); // a click without a drag changed nothing
      return;
    }
    // A segment drawn by dragging: pointer released away from its first point.
    if (this.tool === 'segment' && this.draft.length === 1) {
      const q = this.snapPoint(this.toScene(e));
      if (this.pixels(this.draft[0], q) >= PICK) this.finishSegment(q);
    }
  }

  doubleClick() {
    if (this.tool === 'polygon' && this.draft.length >= 3) this.finishPolygon();
  }

  key(e) {
    const mod = e.ctrlKey || e.metaKey;
    if (mod && e.key.toLowerCase() === 'z') this.undo();
    else if (e.key === 'Delete' || e.key === 'Backspace') this.deleteSelected();
    else if (e.key === 'Escape') {
      this.selected = -1;
      this.setTool(this.tool);
    }
    else if (e.key === 'Enter' && this.tool === 'polygon' && this.draft.length >= 3) this.finishPolygon();
    else if (e.key === 'r' || e.key === 'R') this.transformSelected(((e.shiftKey ? -1 : 1) * Math.PI) / 12, 1);
    else if (e.key === '+' || e.key === '=') this.transformSelected(0, 1.1);
    else if (e.key === '-') this.transformSelected(0, 1 / 1.1);
    else return;
    e.preventDefault();
  }

  pixels(a, b) {
    return Math.hypot(a[0] - b[0], a[1] - b[1]) * this.view.scale;
  }

  patchesFor(a, b) {
    return Math.max(1, Math.round(Math.hypot(b[0] - a[0], b[1] - a[1]) * this.density));
  }

  finishSegment(b) {
    const a = this.draft[0];
    this.draft = [];
    if (this.pixels(a, b) < 1) return;
    this.pushUndo();
    const n = this.patchesFor(a, b);
    const surfaces = [surface(a, b, n)];
    if (this.twoSided) surfaces.push(surface(b, a, n));
    this.model.objects.push({ surfaces });
    this.selected = this.model.objects.length - 1;
    this.onChange('geometry');
  }

  /// Closes the drafted polygon. It faces inwards (a room, counter-clockwise) when it
  /// encloses everything drawn so far, else outwards (an object, clockwise).
  finishPolygon() {
    let pts = this.draft;
    this.draft = [];
    const all = this.model.objects.flatMap(points);
    const room = all.every((p) => inside(p, pts));
    if (signedArea2(pts) > 0 !== room) pts = [...pts].reverse();
    this.pushUndo();
    const surfaces = pts.map((a, k) => {
      const b = pts[(k + 1) % pts.length];
      return surface(a, b, this.patchesFor(a, b));
    });
    this.model.objects.push({ surfaces });
    this.selected = this.model.objects.length - 1;
    this.onChange('geometry');
  }

  // ---- picking ----------------------------------------------------------------------------

  objectAt(p) {
    let best = -1;
    let bestD = PICK / this.view.scale;
    this.model.objects.forEach((o, k) => {
      for (const s of o.surfaces) {
        const d = distanceToSegment(p, s.a, s.b);
        if (d < bestD) [best, bestD] = [k, d];
      }
    });
    return best;
  }

  /// The selection's handles in scene coordinates: rotate (above) and scale (corner).
  handles() {
    if (this.selected < 0) return null;
    const [x0, y0, x1, y1] = bounds(points(this.model.objects[this.selected]));
    const off = 18 / this.view.scale;
    return { rotate: [(x0 + x1) / 2, y1 + off], scale: [x1 + off / 2, y0 - off / 2], box: [x0, y0, x1, y1] };
  }

  handleAt(p) {
    const h = this.handles();
    if (!h) return null;
    for (const kind of ['rotate', 'scale']) if (this.pixels(h[kind], p) <= HANDLE + 2) return kind;
    return null;
  }

  status() {
    const hints = {
      select: 'Click an object to select it; drag to move, ○ to rotate, □ to scale. R / Shift+R rotate 15°, + / − scale, Delete removes, Ctrl+Z undoes.',
      segment: 'Click two points (or drag) to add a segment. Esc cancels.',
      polygon: 'Click the vertices; click the first vertex, double-click or press Enter to close. A polygon around everything is a room (faces inwards), otherwise an object (faces outwards).',
    };
    this.onStatus(hints[this.tool]);
  }

  // ---- drawing ----------------------------------------------------------------------------

  draw() {
    const g = this.g;
    g.setTransform(this.dpr, 0, 0, this.dpr, 0, 0);
    g.clearRect(0, 0, this.cssWidth, this.cssHeight);
    this.drawGrid();
    let patch = 0;
    this.model.objects.forEach((o, k) => {
      for (const s of o.surfaces) patch = this.drawSurface(s, patch, k === this.selected);
    });
    this.drawSelection();
    this.drawDraft();
  }

  drawGrid() {
    if (!this.snap) return;
    const g = this.g;
    const s = this.gridStep();
    // Scene coordinates of the top-left corner.
    const x0 = this.view.cx - this.cssWidth / 2 / this.view.scale;
    const y1 = this.view.cy + this.cssHeight / 2 / this.view.scale;
    g.fillStyle = '#d5d9e0';
    for (let x = Math.floor(x0 / s) * s; ; x += s) {
      const [sx] = this.toScreen([x, 0]);
      if (sx > this.cssWidth) break;
      for (let y = Math.floor(y1 / s) * s; ; y -= s) {
        const [, sy] = this.toScreen([0, y]);
        if (sy > this.cssHeight) break;
        g.fillRect(sx - 0.5, sy - 0.5, 1, 1);
      }
    }
  }

  /// Draws one surface's patches (coloured when colours are set) just in front of it, with
  /// ticks at the cuts; returns the index of the next patch.
  drawSurface(s, first, selected) {
    const g = this.g;
    const [a, b] = [this.toScreen(s.a), this.toScreen(s.b)];
    const len = Math.hypot(b[0] - a[0], b[1] - a[1]) || 1;
    // Front normal on screen: the scene's left normal (−dy, dx), y flipped.
    const nx = (a[1] - b[1]) / len;
    const ny = (b[0] - a[0]) / len;
    const normal = [-nx, -ny];
    const cuts = s.cuts ?? Array.from({ length: s.n - 1 }, (_, k) => (k + 1) / s.n);
    const ts = [0, ...cuts, 1];
    const at = (t, off) => [a[0] + (b[0] - a[0]) * t + normal[0] * off, a[1] + (b[1] - a[1]) * t + normal[1] * off];
    g.lineCap = 'butt';
    for (let k = 0; k + 1 < ts.length; k++) {
      const [p, q] = [at(ts[k], FRONT), at(ts[k + 1], FRONT)];
      g.strokeStyle = this.colours?.[first + k] ?? (selected ? '#1f5fbf' : '#2b2f36');
      g.lineWidth = this.colours ? 4 : selected ? 2.5 : 2;
      g.beginPath();
      g.moveTo(...p);
      g.lineTo(...q);
      g.stroke();
    }
    // Cut ticks, when patches are at least 5 pixels long.
    if (len / (ts.length - 1) >= 5) {
      g.strokeStyle = 'rgba(0,0,0,0.45)';
      g.lineWidth = 1;
      for (const t of cuts) {
        const [p, q] = [at(t, 0), at(t, FRONT + 4)];
        g.beginPath();
        g.moveTo(...p);
        g.lineTo(...q);
        g.stroke();
      }
    }
    // A small arrow-less facing mark at the midpoint.
    const [m, f] = [at(0.5, FRONT), at(0.5, FRONT + 7)];
    g.strokeStyle = selected ? '#1f5fbf' : '#7a808a';
    g.lineWidth = 1;
    g.beginPath();
    g.moveTo(...m);
    g.lineTo(...f);
    g.stroke();
    return first + ts.length - 1;
  }

  drawSelection() {
    const h = this.handles();
    if (!h) return;
    const g = this.g;
    const [x0, y0, x1, y1] = h.box;
    const [p, q] = [this.toScreen([x0, y1]), this.toScreen([x1, y0])];
    g.setLineDash([4, 3]);
    g.strokeStyle = '#1f5fbf';
    g.lineWidth = 1;
    g.strokeRect(p[0] - 4, p[1] - 4, q[0] - p[0] + 8, q[1] - p[1] + 8);
    g.setLineDash([]);
    const r = this.toScreen(h.rotate);
    const s = this.toScreen(h.scale);
    g.fillStyle = '#fff';
    g.beginPath();
    g.arc(r[0], r[1], HANDLE, 0, 2 * Math.PI);
    g.fill();
    g.stroke();
    g.fillRect(s[0] - HANDLE, s[1] - HANDLE, 2 * HANDLE, 2 * HANDLE);
    g.strokeRect(s[0] - HANDLE, s[1] - HANDLE, 2 * HANDLE, 2 * HANDLE);
  }

  drawDraft() {
    if (!this.draft.length) return;
    const g = this.g;
    const pts = [...this.draft, ...(this.hover ? [this.hover] : [])].map((p) => this.toScreen(p));
    g.strokeStyle = '#d1713b';
    g.lineWidth = 2;
    g.setLineDash([6, 4]);
    g.beginPath();
    pts.forEach((p, k) => (k ? g.lineTo(...p) : g.moveTo(...p)));
    g.stroke();
    g.setLineDash([]);
    g.fillStyle = '#d1713b';
    for (const p of pts) g.fillRect(p[0] - 3, p[1] - 3, 6, 6);
  }
}

function distanceToSegment(p, a, b) {
  const [dx, dy] = [b[0] - a[0], b[1] - a[1]];
  const l2 = dx * dx + dy * dy;
  const t = l2 > 0 ? Math.max(0, Math.min(1, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2)) : 0;
  return Math.hypot(p[0] - a[0] - t * dx, p[1] - a[1] - t * dy);
}
