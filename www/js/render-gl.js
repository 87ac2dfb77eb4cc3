// WebGL2 renderer: particles as shaded sphere impostors (point sprites that write the depth of
// the sphere they show), soft contact shadows on the floor in 3D, the domain box and a floor
// grid. Positions and colour scalars come straight from views into wasm memory.

import { BODY_COLOURS, SLEEP_COLOUR, YIELD_COLOURS, VIRIDIS_GLSL } from './colours.js';

const MODE = { body: 0, yield: 1, speed: 2, pressure: 2, plastic_strain: 2, sleeping: 3 };

const PARTICLE_VS = `#version 300 es
layout(location = 0) in vec3 a_pos;
layout(location = 1) in float a_val;
uniform mat4 u_view, u_proj;
uniform float u_radius, u_pxPerUnit, u_maxPoint;
uniform bool u_ortho;
uniform int u_mode;
uniform vec2 u_range;
uniform vec3 u_body[${BODY_COLOURS.length}];
uniform vec3 u_yield[3];
out vec3 v_colour;
out vec3 v_centre;
${VIRIDIS_GLSL}
void main() {
  vec4 vp = u_view * vec4(a_pos, 1.0);
  v_centre = vp.xyz;
  gl_Position = u_proj * vp;
  float w = u_ortho ? 1.0 : max(1e-4, -vp.z);
  gl_PointSize = clamp(2.0 * u_radius * u_pxPerUnit / w, 1.5, u_maxPoint);
  if (u_mode == 0) v_colour = u_body[int(a_val + 0.5) % ${BODY_COLOURS.length}];
  else if (u_mode == 3) v_colour = a_val < 0.0 ? vec3(${SLEEP_COLOUR.join(', ')}) : u_body[int(a_val + 0.5) % ${BODY_COLOURS.length}];
  else if (u_mode == 1) v_colour = u_yield[clamp(int(a_val * 2.0 + 0.5), 0, 2)];
  else v_colour = viridis((a_val - u_range.x) / max(1e-30, u_range.y - u_range.x));
}`;

const PARTICLE_FS = `#version 300 es
precision highp float;
in vec3 v_colour;
in vec3 v_centre;
uniform mat4 u_proj;
uniform float u_radius;
out vec4 o_colour;
void main() {
  vec2 c = gl_PointCoord * 2.0 - 1.0;
  c.y = -c.y;
  float r2 = dot(c, c);
  if (r2 > 1.0) discard;
  vec3 n = vec3(c, sqrt(1.0 - r2));
  vec4 clip = u_proj * vec4(v_centre + n * u_radius, 1.0);
  gl_FragDepth = clip.z / clip.w * 0.5 + 0.5;
  vec3 l = normalize(vec3(-0.35, 0.75, 0.55));
  float diffuse = max(dot(n, l), 0.0);
  float spec = pow(max(dot(n, normalize(l + vec3(0.0, 0.0, 1.0))), 0.0), 32.0);
  vec3 col = v_colour * (0.38 + 0.62 * diffuse) + 0.18 * spec;
  col *= mix(0.72, 1.0, smoothstep(0.0, 0.4, n.z));
  o_colour = vec4(col, 1.0);
}`;

// Contact shadows: every particle flattened onto the floor, drawn once per pixel (stencil).
const SHADOW_VS = `#version 300 es
layout(location = 0) in vec3 a_pos;
uniform mat4 u_viewProj;
uniform float u_radius, u_pxPerUnit, u_height, u_maxPoint;
void main() {
  vec4 clip = u_viewProj * vec4(a_pos.x, 0.0005 * u_height, a_pos.z, 1.0);
  gl_Position = clip;
  float fade = clamp(1.0 - a_pos.y / (0.9 * u_height), 0.45, 1.0);
  gl_PointSize = clamp(2.4 * u_radius * u_pxPerUnit * fade / max(1e-4, clip.w), 1.0, u_maxPoint);
}`;

const SHADOW_FS = `#version 300 es
precision mediump float;
out vec4 o_colour;
void main() {
  vec2 c = gl_PointCoord * 2.0 - 1.0;
  if (dot(c, c) > 1.0) discard;
  o_colour = vec4(0.10, 0.13, 0.20, 0.22);
}`;

const LINE_VS = `#version 300 es
layout(location = 0) in vec3 a_pos;
uniform mat4 u_viewProj;
void main() { gl_Position = u_viewProj * vec4(a_pos, 1.0); }`;

const LINE_FS = `#version 300 es
precision mediump float;
uniform vec4 u_colour;
out vec4 o_colour;
void main() { o_colour = u_colour; }`;

const MARKER_VS = `#version 300 es
uniform mat4 u_viewProj;
uniform vec3 u_at;
uniform float u_size;
void main() { gl_Position = u_viewProj * vec4(u_at, 1.0); gl_PointSize = u_size; }`;

const MARKER_FS = `#version 300 es
precision mediump float;
out vec4 o_colour;
void main() {
  float r = length(gl_PointCoord * 2.0 - 1.0);
  if (r > 1.0 || r < 0.62) discard;
  o_colour = r > 0.82 ? vec4(1.0) : vec4(0.85, 0.1, 0.55, 1.0);
}`;

function compile(gl, vs, fs) {
  const program = gl.createProgram();
  for (const [type, src] of [[gl.VERTEX_SHADER, vs], [gl.FRAGMENT_SHADER, fs]]) {
    const s = gl.createShader(type);
    gl.shaderSource(s, src);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(`shader: ${gl.getShaderInfoLog(s)}`);
    gl.attachShader(program, s);
  }
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) throw new Error(`program: ${gl.getProgramInfoLog(program)}`);
  const uniforms = {};
  const n = gl.getProgramParameter(program, gl.ACTIVE_UNIFORMS);
  for (let i = 0; i < n; i++) {
    const name = gl.getActiveUniform(program, i).name.replace(/\[0\]$/, '');
    uniforms[name] = gl.getUniformLocation(program, name);
  }
  return { program, uniforms };
}

/// A nice grid spacing for a floor `extent` metres wide (1, 2 or 5 × 10^k).
function gridStep(extent) {
  const raw = extent / 12;
  const p = 10 ** Math.floor(Math.log10(raw));
  return [1, 2, 5, 10].map((m) => m * p).find((s) => s >= raw);
}

export class GlRenderer {
  constructor(canvas) {
    const gl = canvas.getContext('webgl2', { antialias: false, stencil: true });
    if (!gl) throw new Error('WebGL2 is not available');
    this.gl = gl;
    this.canvas = canvas;
    this.kind = 'WebGL2';
    this.particlesExact = compile(gl, PARTICLE_VS, PARTICLE_FS);
    // Without the per-fragment sphere depth the depth test can run before shading: cheaper
    // where there is no GPU; spheres then cut each other along flat discs.
    this.particlesFlat = compile(gl, PARTICLE_VS, PARTICLE_FS.replace(/\n  vec4 clip = [^\n]*\n  gl_FragDepth = [^\n]*/, ''));
    this.shadowProgram = compile(gl, SHADOW_VS, SHADOW_FS);
    this.lines = compile(gl, LINE_VS, LINE_FS);
    this.marker = compile(gl, MARKER_VS, MARKER_FS);
    this.posBuffer = gl.createBuffer();
    this.valBuffer = gl.createBuffer();
    this.vao = gl.createVertexArray();
    this.lineVao = gl.createVertexArray();
    this.lineBuffer = gl.createBuffer();
    this.emptyVao = gl.createVertexArray();
    this.dim = 0;
    // The largest point sprite the implementation draws (64 on some, 1024 on others).
    this.maxPoint = gl.getParameter(gl.ALIASED_POINT_SIZE_RANGE)[1];
    this.shadows = true; // contact shadows in 3D
    this.sphereDepth = true; // write each sphere's own depth (exact intersections)
    this.scale = 1; // drawing-buffer resolution relative to the CSS size × devicePixelRatio
  }

  /// The static geometry of a domain of `size` metres.
  setDomain(size) {
    const gl = this.gl;
    this.size = size.slice();
    this.dim = size.length;
    const [w, h, d = 0] = size;
    const floor = [], edges = [];
    if (this.dim === 3) {
      const s = gridStep(Math.max(w, d));
      for (let x = 0; x <= w + 1e-9; x += s) floor.push(x, 0, 0, x, 0, d);
      for (let z = 0; z <= d + 1e-9; z += s) floor.push(0, 0, z, w, 0, z);
      const c = [[0, 0, 0], [w, 0, 0], [w, 0, d], [0, 0, d]];
      for (let i = 0; i < 4; i++) {
        const [a, b] = [c[i], c[(i + 1) % 4]];
        edges.push(...a, ...b);
        edges.push(a[0], h, a[2], b[0], h, b[2]);
        edges.push(a[0], 0, a[2], a[0], h, a[2]);
      }
      this.floorQuad = [0, 0, 0, w, 0, 0, w, 0, d, 0, 0, 0, w, 0, d, 0, 0, d];
    } else {
      const s = gridStep(Math.max(w, h));
      for (let x = 0; x <= w + 1e-9; x += s) floor.push(x, 0, -0.01, x, h, -0.01);
      for (let y = 0; y <= h + 1e-9; y += s) floor.push(0, y, -0.01, w, y, -0.01);
      edges.push(0, 0, 0, w, 0, 0, w, 0, 0, w, h, 0, w, h, 0, 0, h, 0, 0, h, 0, 0, 0, 0);
      this.floorQuad = [0, 0, -0.02, w, 0, -0.02, w, h, -0.02, 0, 0, -0.02, w, h, -0.02, 0, h, -0.02];
    }
    this.gridCount = floor.length / 3;
    this.edgeCount = edges.length / 3;
    const all = new Float32Array([...this.floorQuad, ...floor, ...edges]);
    gl.bindVertexArray(this.lineVao);
    gl.bindBuffer(gl.ARRAY_BUFFER, this.lineBuffer);
    gl.bufferData(gl.ARRAY_BUFFER, all, gl.STATIC_DRAW);
    gl.enableVertexAttribArray(0);
    gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 0, 0);
    gl.bindVertexArray(null);
  }

  resize() {
    const dpr = Math.min(2, window.devicePixelRatio || 1) * this.scale;
    const w = Math.round(this.canvas.clientWidth * dpr), h = Math.round(this.canvas.clientHeight * dpr);
    if (this.canvas.width !== w || this.canvas.height !== h) {
      this.canvas.width = w;
      this.canvas.height = h;
    }
    return dpr;
  }

  /// Draws one frame. `positions` holds `stride` floats per particle (x, y (, z) first) and
  /// `values` one float per particle.
  draw({ camera, positions, stride, values, count, mode, range, radius, marker }) {
    const gl = this.gl;
    const dpr = this.resize();
    const W = this.canvas.width, H = this.canvas.height;
    gl.viewport(0, 0, W, H);
    gl.clearColor(0.93, 0.95, 0.98, 1);
    gl.clearStencil(0);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT | gl.STENCIL_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    const pxPerUnit = camera.pixelsPerMetre() * dpr;

    // Floor (3D) or backdrop (2D), then grid and box edges.
    const L = this.lines;
    gl.useProgram(L.program);
    gl.uniformMatrix4fv(L.uniforms.u_viewProj, false, camera.viewProj);
    gl.bindVertexArray(this.lineVao);
    gl.uniform4f(L.uniforms.u_colour, 1, 1, 1, 1);
    gl.drawArrays(gl.TRIANGLES, 0, 6);
    gl.uniform4f(L.uniforms.u_colour, 0.80, 0.84, 0.90, 1);
    gl.depthMask(false);
    gl.drawArrays(gl.LINES, 6, this.gridCount);
    gl.depthMask(true);

    if (count > 0) {
      gl.bindVertexArray(this.vao);
      gl.bindBuffer(gl.ARRAY_BUFFER, this.posBuffer);
      gl.bufferData(gl.ARRAY_BUFFER, positions, gl.STREAM_DRAW);
      gl.enableVertexAttribArray(0);
      gl.vertexAttribPointer(0, this.dim, gl.FLOAT, false, 4 * stride, 0);
      gl.bindBuffer(gl.ARRAY_BUFFER, this.valBuffer);
      gl.bufferData(gl.ARRAY_BUFFER, values, gl.STREAM_DRAW);
      gl.enableVertexAttribArray(1);
      gl.vertexAttribPointer(1, 1, gl.FLOAT, false, 0, 0);

      if (this.dim === 3 && this.shadows) {
        const S = this.shadowProgram;
        gl.useProgram(S.program);
        gl.uniformMatrix4fv(S.uniforms.u_viewProj, false, camera.viewProj);
        gl.uniform1f(S.uniforms.u_radius, radius);
        gl.uniform1f(S.uniforms.u_pxPerUnit, pxPerUnit);
        gl.uniform1f(S.uniforms.u_height, this.size[1]);
        gl.uniform1f(S.uniforms.u_maxPoint, this.maxPoint);
        gl.enable(gl.BLEND);
        gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
        gl.enable(gl.STENCIL_TEST);
        gl.stencilFunc(gl.EQUAL, 0, 0xff);
        gl.stencilOp(gl.KEEP, gl.KEEP, gl.INCR);
        gl.depthMask(false);
        gl.drawArrays(gl.POINTS, 0, count);
        gl.depthMask(true);
        gl.disable(gl.STENCIL_TEST);
        gl.disable(gl.BLEND);
      }

      const P = this.sphereDepth ? this.particlesExact : this.particlesFlat;
      gl.useProgram(P.program);
      gl.uniformMatrix4fv(P.uniforms.u_view, false, camera.view);
      gl.uniformMatrix4fv(P.uniforms.u_proj, false, camera.proj);
      gl.uniform1f(P.uniforms.u_radius, radius);
      gl.uniform1f(P.uniforms.u_pxPerUnit, pxPerUnit);
      gl.uniform1i(P.uniforms.u_ortho, camera.orthographic ? 1 : 0);
      gl.uniform1f(P.uniforms.u_maxPoint, this.maxPoint);
      gl.uniform1i(P.uniforms.u_mode, MODE[mode] ?? 2);
      gl.uniform2f(P.uniforms.u_range, range[0], range[1]);
      gl.uniform3fv(P.uniforms.u_body, BODY_COLOURS.flat());
      gl.uniform3fv(P.uniforms.u_yield, YIELD_COLOURS.flat());
      gl.drawArrays(gl.POINTS, 0, count);
    }

    gl.useProgram(L.program);
    gl.bindVertexArray(this.lineVao);
    gl.uniform4f(L.uniforms.u_colour, 0.45, 0.50, 0.60, 1);
    gl.drawArrays(gl.LINES, 6 + this.gridCount, this.edgeCount);

    if (marker) {
      const M = this.marker;
      gl.disable(gl.DEPTH_TEST);
      gl.useProgram(M.program);
      gl.bindVertexArray(this.emptyVao);
      gl.uniformMatrix4fv(M.uniforms.u_viewProj, false, camera.viewProj);
      gl.uniform3f(M.uniforms.u_at, marker[0], marker[1], marker[2] ?? 0);
      gl.uniform1f(M.uniforms.u_size, 22 * dpr);
      gl.drawArrays(gl.POINTS, 0, 1);
    }
    gl.bindVertexArray(null);
  }

  /// Waits until the GPU has finished (for timing).
  finish() {
    this.gl.finish();
  }
}
