// An orbit camera (docs/web.md): yaw and pitch around a target at a distance, as
// viewer/camera.c. Column-major 4x4 matrices for WebGL; rays through a pixel for picking.

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const scale = (s, a) => [s * a[0], s * a[1], s * a[2]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
  a[0] * b[1] - a[1] * b[0]];
const normalize = (a) => scale(1 / Math.hypot(...a), a);

export const vec3 = { sub, add, scale, dot, cross, normalize };

export class OrbitCamera {
  constructor() {
    this.target = [0, -1.5, 0];
    this.yaw = 0.6;      // rad about +y
    this.pitch = 0.35;   // rad above the horizon
    this.distance = 11;  // m
    this.fovY = (45 * Math.PI) / 180;
  }

  // Look at a box of the scene (centre and radius, m) from the current direction.
  frame(center, radius) {
    this.target = center.slice();
    this.distance = Math.max(1, (1.6 * radius) / Math.sin(this.fovY / 2));
  }

  eye() {
    const c = Math.cos(this.pitch);
    return add(this.target, scale(this.distance,
      [c * Math.sin(this.yaw), Math.sin(this.pitch), c * Math.cos(this.yaw)]));
  }

  // The camera's axes: right, up and forward (unit).
  axes() {
    const forward = normalize(sub(this.target, this.eye()));
    const right = normalize(cross(forward, [0, 1, 0]));
    return { right, up: cross(right, forward), forward };
  }

  orbit(dx, dy) {
    this.yaw -= dx * 0.008;
    this.pitch = Math.min(1.5, Math.max(-0.2, this.pitch + dy * 0.008));
  }

  // Move the target in the view plane by a drag of (dx, dy) pixels of a @p height-pixel view.
  pan(dx, dy, height) {
    const { right, up } = this.axes();
    const metresPerPixel = (2 * this.distance * Math.tan(this.fovY / 2)) / height;
    this.target = add(this.target, add(scale(-dx * metresPerPixel, right),
      scale(dy * metresPerPixel, up)));
  }

  zoom(factor) {
    this.distance = Math.min(200, Math.max(0.5, this.distance * factor));
  }

  viewProjection(aspect) {
    const near = 0.05, far = 500;
    const f = 1 / Math.tan(this.fovY / 2);
    const p = [f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) / (near - far), -1,
      0, 0, (2 * far * near) / (near - far), 0];
    const { right, up, forward } = this.axes();
    const e = this.eye();
    const v = [right[0], up[0], -forward[0], 0, right[1], up[1], -forward[1], 0,
      right[2], up[2], -forward[2], 0, -dot(right, e), -dot(up, e), dot(forward, e), 1];
    const m = new Float32Array(16);
    for (let c = 0; c < 4; ++c)
      for (let r = 0; r < 4; ++r) {
        let s = 0;
        for (let k = 0; k < 4; ++k) s += p[4 * k + r] * v[4 * c + k];
        m[4 * c + r] = s;
      }
    return m;
  }

  // The ray through pixel (x, y) of a width x height view: origin and unit direction.
  ray(x, y, width, height) {
    const { right, up, forward } = this.axes();
    const t = Math.tan(this.fovY / 2);
    const sx = ((2 * x) / width - 1) * t * (width / height);
    const sy = (1 - (2 * y) / height) * t;
    return { origin: this.eye(), direction: normalize(add(forward, add(scale(sx, right),
      scale(sy, up)))) };
  }

  // Where point p lands in a width x height view (pixels), or null behind the camera.
  project(p, width, height) {
    const { right, up, forward } = this.axes();
    const d = sub(p, this.eye());
    const z = dot(d, forward);
    if (z <= 0) return null;
    const t = Math.tan(this.fovY / 2);
    const sx = dot(d, right) / (z * t * (width / height));
    const sy = dot(d, up) / (z * t);
    return [((sx + 1) * width) / 2, ((1 - sy) * height) / 2];
  }
}
