// The page's WebGL2 renderer (docs/web.md): the bodies' surfaces with normals smooth but split at
// creases sharper than 40 degrees, as femto view's (viewer/creases.c; sleeping bodies dimmed), the
// contacts' normals as lines, a floor with a checker and fog, and planar shadows (the bodies
// flattened onto the floor along the light, drawn once per pixel through the stencil). Modelled
// on viewer/renderer.c's shaders, written for GLSL ES 3.00. Plain WebGL2, no library.

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

// The library's grab colour (src/draw/draw.c, 0xff40c0): the drag's spring, as femto view draws it.
export const grabColor = [1.0, 0x40 / 255, 0xc0 / 255];

// A vertex array reading 3 floats a point from @p buffer every @p stride bytes (0: packed).
function pointsOf(gl, buffer, stride) {
  const vao = gl.createVertexArray();
  gl.bindVertexArray(vao);
  gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
  gl.enableVertexAttribArray(0);
  gl.vertexAttribPointer(0, 3, gl.FLOAT, false, stride, 0);
  gl.bindVertexArray(null);
  return vao;
}

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

// Normals split at creases, as femto view does (viewer/creases.c, docs/viewer.md): a triangle's
// corner takes the mean of the area-weighted normals of the triangles around its vertex whose
// normal is within creaseDegrees of its own (its own always counts), so a hard edge shades flat
// on both sides and a smooth surface stays smooth. Which triangles each corner averages is found
// once, on the rest shape (creaseSplit); corners of a vertex that average the same triangles
// share one drawn vertex (a smooth vertex stays one, a vertex on a crease is split in two or
// more), and each frame only the face normals and those sums are computed (splitNormals).
export const creaseDegrees = 40;

// Every triangle's area-weighted normal (3 floats a triangle) into @p faces.
export function faceNormals(positions, triangles, faces) {
  for (let t = 0, f = 0; t < triangles.length; t += 3, f += 3) {
    const a = 3 * triangles[t], b = 3 * triangles[t + 1], c = 3 * triangles[t + 2];
    const ux = positions[b] - positions[a], uy = positions[b + 1] - positions[a + 1],
      uz = positions[b + 2] - positions[a + 2];
    const vx = positions[c] - positions[a], vy = positions[c + 1] - positions[a + 1],
      vz = positions[c + 2] - positions[a + 2];
    faces[f] = uy * vz - uz * vy;
    faces[f + 1] = uz * vx - ux * vz;
    faces[f + 2] = ux * vy - uy * vx;
  }
  return faces;
}

// The split of a surface (@p triangles into @p positions, the rest shape) at its creases:
// { source: the body's vertex each drawn vertex copies, start and faces: drawn vertex s averages
// faces[start[s] .. start[s + 1]) (triangle numbers), indices: the triangles over the drawn
// vertices }.
export function creaseSplit(positions, triangles, degrees = creaseDegrees) {
  const triangleCount = triangles.length / 3;
  const faces = faceNormals(positions, triangles, new Float64Array(3 * triangleCount));
  let vertexCount = 0;
  for (const v of triangles) vertexCount = Math.max(vertexCount, v + 1);
  // The triangles around every vertex (a counting sort, as creases.c).
  const first = new Int32Array(vertexCount + 1);
  for (const v of triangles) first[v + 1] += 1;
  for (let v = 0; v < vertexCount; ++v) first[v + 1] += first[v];
  const around = new Int32Array(triangles.length);
  const fill = first.slice(0, vertexCount);
  for (let c = 0; c < triangles.length; ++c) around[fill[triangles[c]]++] = (c / 3) | 0;
  const limit = Math.cos(degrees * Math.PI / 180);
  const length = (t) => Math.sqrt(faces[3 * t] * faces[3 * t] + faces[3 * t + 1] * faces[3 * t + 1] +
    faces[3 * t + 2] * faces[3 * t + 2]);
  const source = [], start = [0], averaged = [];
  const indices = new Uint32Array(triangles.length);
  const seen = new Map(); // "vertex:triangles" -> drawn vertex
  for (let c = 0; c < triangles.length; ++c) {
    const t = (c / 3) | 0, v = triangles[c];
    const own = length(t);
    const list = [];
    for (let e = first[v]; e < first[v + 1]; ++e) {
      const n = around[e];
      const dot = faces[3 * t] * faces[3 * n] + faces[3 * t + 1] * faces[3 * n + 1] +
        faces[3 * t + 2] * faces[3 * n + 2];
      if (n === t || dot >= limit * own * length(n)) list.push(n);
    }
    const key = `${v}:${list.join(',')}`;
    let s = seen.get(key);
    if (s === undefined) {
      s = source.length;
      seen.set(key, s);
      source.push(v);
      averaged.push(...list);
      start.push(averaged.length);
    }
    indices[c] = s;
  }
  return { source: Uint32Array.from(source), start: Int32Array.from(start),
    faces: Int32Array.from(averaged), indices };
}

// The drawn vertices' positions (@p out, 3 floats each) copied from the body's @p positions.
export function splitPositions(positions, split, out) {
  const source = split.source;
  for (let s = 0; s < source.length; ++s) {
    const i = 3 * source[s];
    out[3 * s] = positions[i];
    out[3 * s + 1] = positions[i + 1];
    out[3 * s + 2] = positions[i + 2];
  }
  return out;
}

// The drawn vertices' unit normals (@p normals, 3 floats each) from the body's current
// @p positions: each the mean of its triangles' normals (@p faces: scratch, 3 a triangle).
export function splitNormals(positions, triangles, split, faces, normals) {
  faceNormals(positions, triangles, faces);
  const start = split.start, averaged = split.faces;
  for (let s = 0; s + 1 < start.length; ++s) {
    let x = 0, y = 0, z = 0;
    for (let e = start[s]; e < start[s + 1]; ++e) {
      const f = 3 * averaged[e];
      x += faces[f];
      y += faces[f + 1];
      z += faces[f + 2];
    }
    const l = Math.sqrt(x * x + y * y + z * z);
    if (l > 0) {
      normals[3 * s] = x / l;
      normals[3 * s + 1] = y / l;
      normals[3 * s + 2] = z / l;
    } else {
      normals[3 * s] = 0;
      normals[3 * s + 1] = 1;
      normals[3 * s + 2] = 0;
    }
  }
  return normals;
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
    this.lineBuffer = gl.createBuffer();
    this.lineVao = pointsOf(gl, this.lineBuffer, 0);
    this.pointVao = pointsOf(gl, this.lineBuffer, 24); // the lines' starts: every other vertex
    this.lineCount = 0;
    this.grabBuffer = gl.createBuffer();
    this.grabVao = pointsOf(gl, this.grabBuffer, 0);
    this.grabbing = false;
    this.normalsMs = 0; // the time spent on the drawn vertices' normals and positions, all frames
    // Light from above and to the right of the starting camera, travelling down.
    const l = [-0.7, -1.0, -0.25];
    const n = Math.hypot(...l);
    this.light = l.map((x) => x / n);
  }

  // Set up one GPU mesh per body: @p bodies is [{ triangles: Uint32Array, vertexCount,
  // positions }], positions (3 floats a vertex) the rest shape whose creases split the normals.
  setBodies(bodies) {
    const gl = this.gl;
    for (const m of this.meshes) {
      gl.deleteVertexArray(m.vao);
      gl.deleteBuffer(m.positionBuffer);
      gl.deleteBuffer(m.normalBuffer);
      gl.deleteBuffer(m.indexBuffer);
    }
    this.meshes = bodies.map((b, i) => {
      const split = creaseSplit(b.positions, b.triangles);
      const drawn = split.source.length;
      const vao = gl.createVertexArray();
      gl.bindVertexArray(vao);
      const positionBuffer = gl.createBuffer();
      gl.bindBuffer(gl.ARRAY_BUFFER, positionBuffer);
      gl.bufferData(gl.ARRAY_BUFFER, 12 * drawn, gl.DYNAMIC_DRAW);
      gl.enableVertexAttribArray(0);
      gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 0, 0);
      const normalBuffer = gl.createBuffer();
      gl.bindBuffer(gl.ARRAY_BUFFER, normalBuffer);
      gl.bufferData(gl.ARRAY_BUFFER, 12 * drawn, gl.DYNAMIC_DRAW);
      gl.enableVertexAttribArray(1);
      gl.vertexAttribPointer(1, 3, gl.FLOAT, false, 0, 0);
      const indexBuffer = gl.createBuffer();
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, indexBuffer);
      gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, split.indices, gl.STATIC_DRAW);
      gl.bindVertexArray(null);
      return { vao, positionBuffer, normalBuffer, indexBuffer, count: split.indices.length,
        split, positions: new Float32Array(3 * drawn), normals: new Float32Array(3 * drawn),
        faces: new Float32Array(b.triangles.length), triangles: b.triangles,
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

  // The drag's spring (Float32Array of 6 floats: the grabbed point, the target), or null.
  setGrabLine(line) {
    const gl = this.gl;
    this.grabbing = line !== null;
    if (!this.grabbing) return;
    gl.bindBuffer(gl.ARRAY_BUFFER, this.grabBuffer);
    gl.bufferData(gl.ARRAY_BUFFER, line, gl.DYNAMIC_DRAW);
  }

  // Upload body @p i's positions (Float32Array, 3 a vertex) and their normals split at the
  // creases (the time taken adds up in normalsMs); @p asleep dims it.
  updateBody(i, positions, asleep = false) {
    const gl = this.gl;
    const m = this.meshes[i];
    m.asleep = asleep;
    const start = performance.now();
    splitNormals(positions, m.triangles, m.split, m.faces, m.normals);
    splitPositions(positions, m.split, m.positions);
    this.normalsMs += performance.now() - start;
    gl.bindBuffer(gl.ARRAY_BUFFER, m.positionBuffer);
    gl.bufferSubData(gl.ARRAY_BUFFER, 0, m.positions);
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
    if (this.grabbing) this.drawGrab(viewProjection);
    gl.bindVertexArray(null);
  }

  // The drag's spring over everything: a line from the grabbed point to the pointer's target,
  // both ends as large points (a WebGL line is one pixel wide).
  drawGrab(viewProjection) {
    this.drawOverEverything(viewProjection, grabColor, this.grabVao, 1, this.grabVao, 2, 12);
  }

  // The contacts over everything: the lines, and their starts (the contact points) as dots.
  drawContactLines(viewProjection) {
    this.drawOverEverything(viewProjection, contactColor, this.lineVao, this.lineCount,
      this.pointVao, this.lineCount, 4);
  }

  // @p lines lines of @p lineVao and @p points points of @p pointVao (@p size pixels) in
  // @p color, over everything, as debug lines are drawn.
  drawOverEverything(viewProjection, color, lineVao, lines, pointVao, points, size) {
    const gl = this.gl;
    gl.disable(gl.DEPTH_TEST);
    gl.useProgram(this.line.program);
    gl.uniformMatrix4fv(this.line.uniforms.uViewProjection, false, viewProjection);
    gl.uniform3fv(this.line.uniforms.uColor, color);
    gl.bindVertexArray(lineVao);
    gl.uniform1f(this.line.uniforms.uPointSize, 1);
    gl.drawArrays(gl.LINES, 0, 2 * lines);
    gl.uniform1f(this.line.uniforms.uPointSize, size);
    gl.bindVertexArray(pointVao);
    gl.drawArrays(gl.POINTS, 0, points);
    gl.enable(gl.DEPTH_TEST);
  }
}
