// The 3D lab's renderer: plain WebGL2, one program drawing triangles with a colour per
// corner, and an orbit camera. Drawing only: the geometry and colours come from the wasm
// module (patch triangles, the core's Gouraud mesh and tone map).
//
// Plain WebGL2 rather than a vendored three.js: the lab draws coloured triangles and
// nothing else (no textures, lights or scene graph), which takes ~150 lines here, while
// three.js would add ~170 KB gzipped to the page's 800 KB budget and a second copy of
// the colour pipeline.

const VERTEX = `#version 300 es
in vec3 position;
in vec3 colour;
uniform mat4 viewProjection;
out vec3 vColour;
out vec3 vPosition;
void main() {
  vColour = colour;
  vPosition = position;
  gl_Position = viewProjection * vec4(position, 1.0);
}`;

// `shade` > 0 darkens faces turned away from the eye a little, so that a uniformly
// coloured mesh still shows its shape (information colourings); 0 shows the colours as
// given (radiosity is already the light).
const FRAGMENT = `#version 300 es
precision highp float;
in vec3 vColour;
in vec3 vPosition;
uniform float shade;
uniform vec3 eye;
out vec4 outColour;
void main() {
  vec3 n = normalize(cross(dFdx(vPosition), dFdy(vPosition)));
  float facing = abs(dot(n, normalize(eye - vPosition)));
  outColour = vec4(shade > 0.0 ? vColour * (1.0 - shade + shade * facing) : vColour, 1.0);
}`;

function compile(gl, type, source) {
  const s = gl.createShader(type);
  gl.shaderSource(s, source);
  gl.compileShader(s);
  if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
  return s;
}

function perspective(fovy, aspect, near, far) {
  const f = 1 / Math.tan(fovy / 2);
  const nf = 1 / (near - far);
  return [f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) * nf, -1, 0, 0, 2 * far * near * nf, 0];
}

function lookAt(eye, target, up) {
  const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const norm = (a) => { const l = Math.hypot(...a) || 1; return a.map((x) => x / l); };
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const z = norm(sub(eye, target));
  const x = norm(cross(up, z));
  const y = cross(z, x);
  return [x[0], y[0], z[0], 0, x[1], y[1], z[1], 0, x[2], y[2], z[2], 0, -dot(x, eye), -dot(y, eye), -dot(z, eye), 1];
}

function multiply(a, b) {
  const out = new Array(16).fill(0);
  for (let c = 0; c < 4; c++) {
    for (let r = 0; r < 4; r++) {
      for (let k = 0; k < 4; k++) out[c * 4 + r] += a[k * 4 + r] * b[c * 4 + k];
    }
  }
  return out;
}

/// A WebGL2 view of one mesh on `canvas`, with an orbit camera driven by the pointer.
export class View3 {
  constructor(canvas) {
    this.canvas = canvas;
    const gl = canvas.getContext('webgl2', { antialias: true, preserveDrawingBuffer: true });
    if (!gl) throw new Error('this browser has no WebGL2');
    this.gl = gl;
    const program = gl.createProgram();
    gl.attachShader(program, compile(gl, gl.VERTEX_SHADER, VERTEX));
    gl.attachShader(program, compile(gl, gl.FRAGMENT_SHADER, FRAGMENT));
    gl.linkProgram(program);
    if (!gl.getProgramParameter(program, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(program));
    this.program = program;
    this.uniforms = {
      viewProjection: gl.getUniformLocation(program, 'viewProjection'),
      shade: gl.getUniformLocation(program, 'shade'),
      eye: gl.getUniformLocation(program, 'eye'),
    };
    this.vao = gl.createVertexArray();
    this.positionBuffer = gl.createBuffer();
    this.colourBuffer = gl.createBuffer();
    this.count = 0;
    // Edges (a refined mesh's elements): lines in one dark colour
    this.edgeVao = gl.createVertexArray();
    this.edgeBuffer = gl.createBuffer();
    this.edgeCount = 0;
    this.shade = 0.35;
    // From the front right (−z, +x), as the Cornell boxes are seen
    this.camera = { target: [0, 0, 0], radius: 1, yaw: Math.PI - 0.5, pitch: 0.3, distance: 2.8 };
    this.listen();
    new ResizeObserver(() => this.draw()).observe(canvas);
  }

  /// Fits the camera to the box [x0, y0, z0, x1, y1, z1].
  fit(b) {
    const c = this.camera;
    c.target = [(b[0] + b[3]) / 2, (b[1] + b[4]) / 2, (b[2] + b[5]) / 2];
    c.radius = Math.hypot(b[3] - b[0], b[4] - b[1], b[5] - b[2]) / 2 || 1;
    c.distance = 2.8 * c.radius;
  }

  /// Triangles (`positions`, 9 floats each) with a colour per corner (`colours`, sRGB bytes);
  /// `edges`, line segments (6 floats each) drawn over them, or none.
  setMesh(positions, colours, shade, edges = null) {
    const gl = this.gl;
    gl.bindVertexArray(this.vao);
    gl.bindBuffer(gl.ARRAY_BUFFER, this.positionBuffer);
    gl.bufferData(gl.ARRAY_BUFFER, positions, gl.STATIC_DRAW);
    const position = gl.getAttribLocation(this.program, 'position');
    gl.enableVertexAttribArray(position);
    gl.vertexAttribPointer(position, 3, gl.FLOAT, false, 0, 0);
    gl.bindBuffer(gl.ARRAY_BUFFER, this.colourBuffer);
    gl.bufferData(gl.ARRAY_BUFFER, colours, gl.STATIC_DRAW);
    const colour = gl.getAttribLocation(this.program, 'colour');
    gl.enableVertexAttribArray(colour);
    gl.vertexAttribPointer(colour, 3, gl.UNSIGNED_BYTE, true, 0, 0);
    gl.bindVertexArray(null);
    this.count = positions.length / 3;
    this.shade = shade;
    this.edgeCount = 0;
    if (edges?.length) {
      gl.bindVertexArray(this.edgeVao);
      gl.bindBuffer(gl.ARRAY_BUFFER, this.edgeBuffer);
      gl.bufferData(gl.ARRAY_BUFFER, edges, gl.STATIC_DRAW);
      gl.enableVertexAttribArray(position);
      gl.vertexAttribPointer(position, 3, gl.FLOAT, false, 0, 0);
      gl.disableVertexAttribArray(colour);
      gl.bindVertexArray(null);
      this.edgeCount = edges.length / 3;
    }
    this.draw();
  }

  /// The eye position for the current camera.
  eye() {
    const c = this.camera;
    const cp = Math.cos(c.pitch);
    return [
      c.target[0] + c.distance * cp * Math.sin(c.yaw),
      c.target[1] + c.distance * Math.sin(c.pitch),
      c.target[2] + c.distance * cp * Math.cos(c.yaw),
    ];
  }

  /// Moves the camera to look at the target from unit direction `d` at `radii` radii.
  lookFrom(d, radii) {
    const c = this.camera;
    c.yaw = Math.atan2(d[0], d[2]);
    c.pitch = Math.asin(Math.max(-1, Math.min(1, d[1])));
    c.distance = radii * c.radius;
    this.draw();
  }

  draw() {
    const { gl, canvas } = this;
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(canvas.clientWidth * dpr));
    const h = Math.max(1, Math.round(canvas.clientHeight * dpr));
    if (canvas.width !== w || canvas.height !== h) [canvas.width, canvas.height] = [w, h];
    gl.viewport(0, 0, w, h);
    gl.clearColor(0.125, 0.141, 0.173, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    if (this.count === 0) return;
    const c = this.camera;
    const eye = this.eye();
    // Near the poles the up vector tips over: keep it perpendicular-ish
    const up = Math.abs(Math.cos(c.pitch)) < 1e-3 ? [Math.sin(c.yaw), 0, Math.cos(c.yaw)] : [0, 1, 0];
    const proj = perspective(Math.PI / 4, w / h, c.distance / 100, c.distance + 4 * c.radius);
    gl.enable(gl.DEPTH_TEST);
    // Patches face one side (enclosures inwards): their backs are not drawn, so the near
    // walls of a room seen from outside are open.
    gl.enable(gl.CULL_FACE);
    gl.cullFace(gl.BACK);
    gl.frontFace(gl.CCW);
    gl.useProgram(this.program);
    gl.uniformMatrix4fv(this.uniforms.viewProjection, false, multiply(proj, lookAt(eye, c.target, up)));
    gl.uniform1f(this.uniforms.shade, this.shade);
    gl.uniform3fv(this.uniforms.eye, eye);
    // The faces a little behind their edges
    gl.enable(gl.POLYGON_OFFSET_FILL);
    gl.polygonOffset(1, 1);
    gl.bindVertexArray(this.vao);
    gl.drawArrays(gl.TRIANGLES, 0, this.count);
    gl.disable(gl.POLYGON_OFFSET_FILL);
    if (this.edgeCount > 0) {
      gl.uniform1f(this.uniforms.shade, 0);
      gl.bindVertexArray(this.edgeVao);
      gl.vertexAttrib3f(gl.getAttribLocation(this.program, 'colour'), 0.08, 0.08, 0.08);
      gl.drawArrays(gl.LINES, 0, this.edgeCount);
    }
    gl.bindVertexArray(null);
  }

  listen() {
    const canvas = this.canvas;
    let drag = null;
    canvas.addEventListener('pointerdown', (e) => {
      drag = { x: e.clientX, y: e.clientY };
      canvas.setPointerCapture(e.pointerId);
    });
    canvas.addEventListener('pointermove', (e) => {
      if (!drag) return;
      const c = this.camera;
      c.yaw -= (e.clientX - drag.x) * 0.01;
      c.pitch = Math.max(-1.55, Math.min(1.55, c.pitch + (e.clientY - drag.y) * 0.01));
      drag = { x: e.clientX, y: e.clientY };
      this.draw();
    });
    canvas.addEventListener('pointerup', () => { drag = null; });
    canvas.addEventListener('wheel', (e) => {
      e.preventDefault();
      const c = this.camera;
      c.distance = Math.max(0.05 * c.radius, Math.min(20 * c.radius, c.distance * Math.exp(e.deltaY * 0.001)));
      this.draw();
    }, { passive: false });
  }
}
