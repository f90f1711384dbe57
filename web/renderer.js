// The page's WebGL2 renderer (docs/web.md): the bodies' surfaces with smooth normals (sleeping
// ones dimmed), the contacts' normals as lines, a floor with a checker and fog, and planar shadows (the bodies flattened onto the floor along the
// light, drawn once per pixel through the stencil). Modelled on viewer/renderer.c's shaders,
// written for GLSL ES 3.00. Plain WebGL2, no library.

const bodyVertex = `#version 300 es
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
uniform mat4 uViewProjection;
uniform vec3 uLight;      // shadow pass: the direction the light travels
uniform float uFloor;     // shadow pass: the floor's height
uniform int uShadow;
out vec3 vWorld;
out vec3 vNormal;
void main() {
  vec3 p = aPosition;
  if (uShadow == 1) {
    // Flatten onto the floor along the light (a hair above it, against z-fighting).
    float t = (p.y - uFloor) / max(-uLight.y, 1e-3);
    p = p + t * uLight;
    p.y = uFloor + 0.002;
  }
  vWorld = p;
  vNormal = aNormal;
  gl_Position = uViewProjection * vec4(p, 1.0);
}`;

const bodyFragment = `#version 300 es
precision highp float;
precision highp int;
in vec3 vWorld;
in vec3 vNormal;
uniform vec3 uColor;
uniform vec3 uEye;
uniform vec3 uLight;
uniform int uShadow;
out vec4 color;
void main() {
  if (uShadow == 1) { color = vec4(0.0, 0.0, 0.0, 0.35); return; }
  vec3 n = normalize(vNormal);
  if (!gl_FrontFacing) n = -n;
  vec3 l = -uLight;
  vec3 v = normalize(uEye - vWorld);
  float diffuse = max(dot(n, l), 0.0);
  float specular = pow(max(dot(n, normalize(l + v)), 0.0), 48.0) * 0.35;
  float sky = 0.5 + 0.5 * n.y; // hemisphere ambient: sky above, ground below
  vec3 ambient = mix(vec3(0.26, 0.24, 0.22), vec3(0.46, 0.5, 0.56), sky);
  vec3 c = uColor * (ambient + 0.75 * diffuse) + vec3(specular);
  color = vec4(min(c, vec3(1.0)), 1.0);
}`;

const floorVertex = `#version 300 es
layout(location = 0) in vec2 aCorner;
uniform mat4 uViewProjection;
uniform vec3 uCenter;
uniform float uSize;
out vec3 vWorld;
void main() {
  vWorld = uCenter + vec3(aCorner.x * uSize, 0.0, aCorner.y * uSize);
  gl_Position = uViewProjection * vec4(vWorld, 1.0);
}`;

const floorFragment = `#version 300 es
precision highp float;
precision highp int;
in vec3 vWorld;
uniform vec3 uEye;
uniform vec3 uFog;
uniform vec3 uCenter;
uniform float uSize;
out vec4 color;
void main() {
  vec2 cell = floor(vWorld.xz / 1.0);
  float checker = mod(cell.x + cell.y, 2.0);
  vec3 c = mix(vec3(0.55, 0.56, 0.58), vec3(0.63, 0.64, 0.66), checker);
  // Fine lines every metre, fading with distance.
  vec2 f = abs(fract(vWorld.xz) - 0.5);
  float line = smoothstep(0.485, 0.5, max(f.x, f.y));
  c = mix(c, vec3(0.45), 0.4 * line);
  float fade = smoothstep(0.45 * uSize, uSize, length(vWorld.xz - uCenter.xz));
  c = mix(c, uFog, fade);
  color = vec4(pow(c, vec3(1.0 / 2.2)), 1.0);
}`;

// The contacts' lines and points (fm_drawContacts' colour), drawn over everything as debug
// lines are: a floor contact's normal points up into the body that rests on it.
const lineVertex = `#version 300 es
layout(location = 0) in vec3 aPosition;
uniform mat4 uViewProjection;
uniform float uPointSize;
void main() {
  gl_Position = uViewProjection * vec4(aPosition, 1.0);
  gl_PointSize = uPointSize;
}`;

const lineFragment = `#version 300 es
precision highp float;
uniform vec3 uColor;
out vec4 color;
void main() { color = vec4(uColor, 1.0); }`;

// The library's contact colour (src/draw/draw.c, 0xffd000).
export const contactColor = [1.0, 0xd0 / 255, 0.0];

// A sleeping body's colour: dimmed toward grey, as femto view (viewer/draw_list.c) and Box2D.
export function dimmed(color) {
  return color.map((c) => 0.45 * c + 0.55 * 0.55);
}

function compile(gl, type, source) {
  const shader = gl.createShader(type);
  gl.shaderSource(shader, source);
  gl.compileShader(shader);
  if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS))
    throw new Error('shader: ' + gl.getShaderInfoLog(shader));
  return shader;
}

function program(gl, vertex, fragment) {
  const p = gl.createProgram();
  gl.attachShader(p, compile(gl, gl.VERTEX_SHADER, vertex));
  gl.attachShader(p, compile(gl, gl.FRAGMENT_SHADER, fragment));
  gl.linkProgram(p);
  if (!gl.getProgramParameter(p, gl.LINK_STATUS))
    throw new Error('program: ' + gl.getProgramInfoLog(p));
  const uniforms = {};
  const count = gl.getProgramParameter(p, gl.ACTIVE_UNIFORMS);
  for (let i = 0; i < count; ++i) {
    const name = gl.getActiveUniform(p, i).name;
    uniforms[name] = gl.getUniformLocation(p, name);
  }
  return { program: p, uniforms };
}

// Body colours: the viewer's warm house first, then distinct hues.
const palette = [
  [0.85, 0.45, 0.25], [0.25, 0.55, 0.85], [0.4, 0.75, 0.35],
  [0.85, 0.75, 0.3], [0.65, 0.4, 0.8], [0.3, 0.75, 0.75],
];

export const fogColor = [0.82, 0.86, 0.9];

// Area-weighted vertex normals of the surface triangles (interior vertices keep zero: they are
// never drawn).
export function smoothNormals(positions, triangles, normals) {
  normals.fill(0);
  for (let t = 0; t < triangles.length; t += 3) {
    const a = 3 * triangles[t], b = 3 * triangles[t + 1], c = 3 * triangles[t + 2];
    const ux = positions[b] - positions[a], uy = positions[b + 1] - positions[a + 1],
      uz = positions[b + 2] - positions[a + 2];
    const vx = positions[c] - positions[a], vy = positions[c + 1] - positions[a + 1],
      vz = positions[c + 2] - positions[a + 2];
    const nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
    for (const k of [a, b, c]) {
      normals[k] += nx;
      normals[k + 1] += ny;
      normals[k + 2] += nz;
    }
  }
}

export class Renderer {
  constructor(canvas) {
    const gl = canvas.getContext('webgl2', { antialias: true, stencil: true,
      preserveDrawingBuffer: true });
    if (!gl) throw new Error('this browser has no WebGL2');
    this.gl = gl;
    this.canvas = canvas;
    this.body = program(gl, bodyVertex, bodyFragment);
    this.floor = program(gl, floorVertex, floorFragment);
    this.floorVao = gl.createVertexArray();
    gl.bindVertexArray(this.floorVao);
    const corners = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, corners);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array([-1, -1, 1, -1, 1, 1, -1, 1]), gl.STATIC_DRAW);
    gl.enableVertexAttribArray(0);
    gl.vertexAttribPointer(0, 2, gl.FLOAT, false, 0, 0);
    gl.bindVertexArray(null);
    this.meshes = [];
    this.line = program(gl, lineVertex, lineFragment);
    this.lineVao = gl.createVertexArray();
    this.lineBuffer = gl.createBuffer();
    gl.bindVertexArray(this.lineVao);
    gl.bindBuffer(gl.ARRAY_BUFFER, this.lineBuffer);
    gl.enableVertexAttribArray(0);
    gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 0, 0);
    this.pointVao = gl.createVertexArray(); // the lines' starts: every other vertex
    gl.bindVertexArray(this.pointVao);
    gl.enableVertexAttribArray(0);
    gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 24, 0);
    gl.bindVertexArray(null);
    this.lineCount = 0;
    // Light from above and to the right of the starting camera, travelling down.
    const l = [-0.7, -1.0, -0.25];
    const n = Math.hypot(...l);
    this.light = l.map((x) => x / n);
  }

  // Set up one GPU mesh per body: @p bodies is [{ triangles: Uint32Array, vertexCount }].
  setBodies(bodies) {
    const gl = this.gl;
    for (const m of this.meshes) {
      gl.deleteVertexArray(m.vao);
      gl.deleteBuffer(m.positionBuffer);
      gl.deleteBuffer(m.normalBuffer);
      gl.deleteBuffer(m.indexBuffer);
    }
    this.meshes = bodies.map((b, i) => {
      const vao = gl.createVertexArray();
      gl.bindVertexArray(vao);
      const positionBuffer = gl.createBuffer();
      gl.bindBuffer(gl.ARRAY_BUFFER, positionBuffer);
      gl.bufferData(gl.ARRAY_BUFFER, 12 * b.vertexCount, gl.DYNAMIC_DRAW);
      gl.enableVertexAttribArray(0);
      gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 0, 0);
      const normalBuffer = gl.createBuffer();
      gl.bindBuffer(gl.ARRAY_BUFFER, normalBuffer);
      gl.bufferData(gl.ARRAY_BUFFER, 12 * b.vertexCount, gl.DYNAMIC_DRAW);
      gl.enableVertexAttribArray(1);
      gl.vertexAttribPointer(1, 3, gl.FLOAT, false, 0, 0);
      const indexBuffer = gl.createBuffer();
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, indexBuffer);
      gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, b.triangles, gl.STATIC_DRAW);
      gl.bindVertexArray(null);
      return { vao, positionBuffer, normalBuffer, indexBuffer, count: b.triangles.length,
        normals: new Float32Array(3 * b.vertexCount), triangles: b.triangles,
        color: palette[i % palette.length], asleep: false };
    });
  }

  // The contacts' lines to draw (Float32Array, 6 floats a line: point, tip), or none.
  setContactLines(lines) {
    const gl = this.gl;
    this.lineCount = lines.length / 6;
    if (this.lineCount === 0) return;
    gl.bindBuffer(gl.ARRAY_BUFFER, this.lineBuffer);
    gl.bufferData(gl.ARRAY_BUFFER, lines, gl.DYNAMIC_DRAW);
  }

  // Upload body @p i's positions (Float32Array, 3 a vertex) and their normals; @p asleep dims it.
  updateBody(i, positions, asleep = false) {
    const gl = this.gl;
    const m = this.meshes[i];
    m.asleep = asleep;
    smoothNormals(positions, m.triangles, m.normals);
    gl.bindBuffer(gl.ARRAY_BUFFER, m.positionBuffer);
    gl.bufferSubData(gl.ARRAY_BUFFER, 0, positions);
    gl.bindBuffer(gl.ARRAY_BUFFER, m.normalBuffer);
    gl.bufferSubData(gl.ARRAY_BUFFER, 0, m.normals);
  }

  // Draw a frame seen by @p camera (camera.js) over a floor at @p floorHeight.
  draw(camera, floorHeight) {
    const gl = this.gl;
    const canvas = this.canvas;
    const dpr = window.devicePixelRatio || 1;
    const width = Math.max(1, Math.round(canvas.clientWidth * dpr));
    const height = Math.max(1, Math.round(canvas.clientHeight * dpr));
    if (canvas.width !== width || canvas.height !== height) {
      canvas.width = width;
      canvas.height = height;
    }
    gl.viewport(0, 0, width, height);
    gl.clearColor(...fogColor.map((c) => Math.pow(c, 1 / 2.2)), 1);
    gl.clearStencil(0);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT | gl.STENCIL_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    const viewProjection = camera.viewProjection(width / height);
    const eye = camera.eye();

    // The floor, centred under the camera's target.
    gl.useProgram(this.floor.program);
    let u = this.floor.uniforms;
    const size = Math.max(40, 6 * camera.distance);
    gl.uniformMatrix4fv(u.uViewProjection, false, viewProjection);
    gl.uniform3f(u.uCenter, camera.target[0], floorHeight, camera.target[2]);
    gl.uniform1f(u.uSize, size);
    gl.uniform3fv(u.uEye, eye);
    gl.uniform3fv(u.uFog, fogColor);
    gl.bindVertexArray(this.floorVao);
    gl.drawArrays(gl.TRIANGLE_FAN, 0, 4);

    // Shadows: every body flattened on the floor, each pixel darkened once (stencil).
    gl.useProgram(this.body.program);
    u = this.body.uniforms;
    gl.uniformMatrix4fv(u.uViewProjection, false, viewProjection);
    gl.uniform3fv(u.uLight, this.light);
    gl.uniform3fv(u.uEye, eye);
    gl.uniform1f(u.uFloor, floorHeight);
    if (eye[1] > floorHeight) {
      gl.uniform1i(u.uShadow, 1);
      gl.enable(gl.BLEND);
      gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
      gl.enable(gl.STENCIL_TEST);
      gl.stencilFunc(gl.EQUAL, 0, 0xff);
      gl.stencilOp(gl.KEEP, gl.KEEP, gl.INCR);
      gl.depthMask(false);
      for (const m of this.meshes) {
        gl.bindVertexArray(m.vao);
        gl.drawElements(gl.TRIANGLES, m.count, gl.UNSIGNED_INT, 0);
      }
      gl.depthMask(true);
      gl.disable(gl.STENCIL_TEST);
      gl.disable(gl.BLEND);
    }

    // The bodies.
    gl.uniform1i(u.uShadow, 0);
    for (const m of this.meshes) {
      gl.uniform3fv(u.uColor, m.asleep ? dimmed(m.color) : m.color);
      gl.bindVertexArray(m.vao);
      gl.drawElements(gl.TRIANGLES, m.count, gl.UNSIGNED_INT, 0);
    }
    if (this.lineCount > 0) this.drawContactLines(viewProjection);
    gl.bindVertexArray(null);
  }

  // The contacts over everything: the lines, and their starts (the contact points) as dots.
  drawContactLines(viewProjection) {
    const gl = this.gl;
    gl.disable(gl.DEPTH_TEST);
    gl.useProgram(this.line.program);
    gl.uniformMatrix4fv(this.line.uniforms.uViewProjection, false, viewProjection);
    gl.uniform3fv(this.line.uniforms.uColor, contactColor);
    gl.bindVertexArray(this.lineVao);
    gl.uniform1f(this.line.uniforms.uPointSize, 1);
    gl.drawArrays(gl.LINES, 0, 2 * this.lineCount);
    gl.uniform1f(this.line.uniforms.uPointSize, 4);
    gl.bindVertexArray(this.pointVao);
    gl.drawArrays(gl.POINTS, 0, this.lineCount);
    gl.enable(gl.DEPTH_TEST);
  }
}
