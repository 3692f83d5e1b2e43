// The 3D view of a student's page: draws with WebGL (no library) the scene the server built with the 3D
// viewer's scene code (vessel_gym/ui/view3d_scene.py): the harbour's meshes, the goal and start outlines, the
// hulls, the sea grid and its wave components. This file only places and draws them.
// Scene frame: x east, y north, z up, m. A ship's frame: x starboard, y forward (heading 0 = north).
"use strict";

(function () {
  const VS = `
attribute vec3 p; attribute vec3 nrm;
uniform mat4 vp; uniform vec4 pose;  // pose: x, y, cos(heading), sin(heading)
varying vec3 vn; varying float dist;
void main() {
  float c = pose.z, s = pose.w;  // clockwise heading: starboard (+x) turns to -north, forward (+y) to east
  vec3 w = vec3(c * p.x + s * p.y + pose.x, -s * p.x + c * p.y + pose.y, p.z);
  vn = vec3(c * nrm.x + s * nrm.y, -s * nrm.x + c * nrm.y, nrm.z);
  gl_Position = vp * vec4(w, 1.0);
  dist = gl_Position.w;
}`;
  const FS = `
precision mediump float;
uniform vec3 rgb; uniform float alpha; uniform vec3 sun; uniform vec3 sky; uniform vec2 fog;
varying vec3 vn; varying float dist;
void main() {
  float lambert = abs(dot(normalize(vn), sun));  // both sides lit: outlines are drawn open
  vec3 col = rgb * (0.55 + 0.45 * lambert);
  float f = clamp((dist - fog.x) / (fog.y - fog.x), 0.0, 1.0);
  gl_FragColor = vec4(mix(col, sky, f), alpha);
}`;
  // the sun from the south-west at 50 deg elevation, as the 3D viewer lights its scene
  const EL = 50 * Math.PI / 180, AZ = 225 * Math.PI / 180;
  const SUN = [Math.sin(AZ) * Math.cos(EL), Math.cos(AZ) * Math.cos(EL), Math.sin(EL)];
  const SKY = [205 / 255, 218 / 255, 232 / 255];
  const MAX_FPS = 20;

  function shader(gl, type, text) {
    const s = gl.createShader(type);
    gl.shaderSource(s, text);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    return s;
  }

  // flat-shaded triangles: every face its own three vertices with the face's normal
  function flat(v, f) {
    const pos = new Float32Array(f.length * 3), nrm = new Float32Array(f.length * 3);
    for (let t = 0; t < f.length; t += 3) {
      const a = f[t] * 3, b = f[t + 1] * 3, c = f[t + 2] * 3;
      const ux = v[b] - v[a], uy = v[b + 1] - v[a + 1], uz = v[b + 2] - v[a + 2];
      const wx = v[c] - v[a], wy = v[c + 1] - v[a + 1], wz = v[c + 2] - v[a + 2];
      let nx = uy * wz - uz * wy, ny = uz * wx - ux * wz, nz = ux * wy - uy * wx;
      const len = Math.hypot(nx, ny, nz) || 1;
      nx /= len; ny /= len; nz /= len;
      for (let k = 0; k < 3; k++) {
        const i = f[t + k] * 3, o = (t + k) * 3;
        pos[o] = v[i]; pos[o + 1] = v[i + 1]; pos[o + 2] = v[i + 2];
        nrm[o] = nx; nrm[o + 1] = ny; nrm[o + 2] = nz;
      }
    }
    return { pos, nrm };
  }

  function mul(a, b) {  // column-major 4x4
    const o = new Float32Array(16);
    for (let c = 0; c < 4; c++) for (let r = 0; r < 4; r++) {
      let s = 0;
      for (let k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
      o[c * 4 + r] = s;
    }
    return o;
  }
  function perspective(fovy, aspect, near, far) {
    const f = 1 / Math.tan(fovy / 2), nf = 1 / (near - far);
    return new Float32Array([f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) * nf, -1, 0, 0, 2 * far * near * nf, 0]);
  }
  function lookAt(eye, at, up) {
    const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    const norm = (a) => { const l = Math.hypot(a[0], a[1], a[2]) || 1; return [a[0] / l, a[1] / l, a[2] / l]; };
    const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
    const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    const z = norm(sub(eye, at)), x = norm(cross(up, z)), y = cross(z, x);
    return new Float32Array([x[0], y[0], z[0], 0, x[1], y[1], z[1], 0, x[2], y[2], z[2], 0,
      -dot(x, eye), -dot(y, eye), -dot(z, eye), 1]);
  }

  // Scene3D(canvas, scene): scene is the welcome's scene3d; update(state, ownShip) takes each state.
  function Scene3D(canvas, scene) {
    const gl = canvas.getContext("webgl", { antialias: true });
    this.canvas = canvas; this.gl = gl; this.scene = scene; this.frames = 0; this.camera = "chase";
    this.own = null; this.others = []; this.t = 0; this.tAt = 0; this.rate = 0; this.vp = null;
    if (!gl) { this.error = "no WebGL in this browser"; return; }
    const prog = gl.createProgram();
    gl.attachShader(prog, shader(gl, gl.VERTEX_SHADER, VS));
    gl.attachShader(prog, shader(gl, gl.FRAGMENT_SHADER, FS));
    gl.linkProgram(prog);
    if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(prog));
    this.prog = prog;
    this.loc = {};
    for (const a of ["p", "nrm"]) this.loc[a] = gl.getAttribLocation(prog, a);
    for (const u of ["vp", "pose", "rgb", "alpha", "sun", "sky", "fog"]) this.loc[u] = gl.getUniformLocation(prog, u);
    const mesh = (m) => {
      const { pos, nrm } = flat(m.v, m.f);
      return { pos: this.buffer(pos), nrm: this.buffer(nrm), n: pos.length / 3, rgb: m.rgb, alpha: m.opacity };
    };
    this.harbour = scene.meshes.map(mesh);
    this.hulls = {};
    for (const [name, ms] of Object.entries(scene.hulls)) this.hulls[name] = ms.map(mesh);
    this.rings = scene.rings.map((r) => ({ pos: this.buffer(new Float32Array(r.v)), n: r.v.length / 3, rgb: r.rgb }));
    const sea = scene.sea, m = sea.x.length;
    this.seaPos = new Float32Array(m * 3);
    this.seaNrm = new Float32Array(m * 3);
    for (let i = 0; i < m; i++) { this.seaPos[3 * i] = sea.x[i]; this.seaPos[3 * i + 1] = sea.y[i]; this.seaNrm[3 * i + 2] = 1; }
    this.seaBuf = this.buffer(this.seaPos, gl.DYNAMIC_DRAW);
    this.seaNrmBuf = this.buffer(this.seaNrm, gl.DYNAMIC_DRAW);
    this.seaIdx = gl.createBuffer();
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.seaIdx);
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, new Uint16Array(sea.f), gl.STATIC_DRAW);
    this.seaN = sea.f.length;
    const [x0, x1, y0, y1] = scene.extent;
    this.span = Math.max(x1 - x0, y1 - y0);
    this.last = 0;
    // a frame when something moved (a state, the camera, the canvas's size: request()), or at MAX_FPS while
    // the sea has waves; nothing between (software WebGL on a loaded laptop takes the CPU the page needs)
    this.pending = false;
    this.waves = scene.sea.components.length > 0;
    this.request();
  }

  Scene3D.prototype.request = function () {
    if (this.pending || !this.gl) return;
    this.pending = true;
    const wait = Math.max(0, this.last + 1000 / MAX_FPS - performance.now());
    setTimeout(() => requestAnimationFrame((now) => {
      this.pending = false;
      this.last = now;
      this.draw(now);
      if (this.waves) this.request();
    }), wait);
  };

  Scene3D.prototype.buffer = function (data, usage) {
    const gl = this.gl, b = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, b);
    gl.bufferData(gl.ARRAY_BUFFER, data, usage || gl.STATIC_DRAW);
    return b;
  };

  // a state: the own ship's truth (n, e, hdg of its entry in ships) and the others as its AIS has them
  Scene3D.prototype.update = function (m, ownShip) {
    const now = performance.now();
    if (this.tAt && m.t_s > this.t) this.rate = Math.min(8, (m.t_s - this.t) / ((now - this.tAt) / 1000));
    this.t = m.t_s; this.tAt = now;
    const o = (m.ships || []).find((s) => s.k === ownShip);
    if (o && o.n !== null && o.hdg !== null) this.own = { x: o.e, y: o.n, hdg: o.hdg, ended: o.outcome !== "running" };
    this.others = (m.ais || []).map((a) => ({ x: a.e, y: a.n, hdg: a.cog, hull: a.own ? "own" : a.name,
      rgb: a.own ? this.scene.rgb.student : this.scene.rgb.traffic }));
    this.request();
  };

  Scene3D.prototype.cameraPose = function () {
    const L = this.scene.L, o = this.own, [x0, x1, y0, y1] = this.scene.extent;
    if (this.camera === "harbour" || !o) {  // the whole harbour, north up, from the south and above
      const c = [(x0 + x1) / 2, (y0 + y1) / 2, 0];
      return { eye: [c[0], c[1] - 0.35 * this.span, 0.85 * this.span], at: c };
    }
    const h = o.hdg * Math.PI / 180, fx = Math.sin(h), fy = Math.cos(h);
    const [astern, above, ahead] = this.scene.chase_L;
    return { eye: [o.x - astern * L * fx, o.y - astern * L * fy, above * L], at: [o.x + ahead * L * fx, o.y + ahead * L * fy, 0] };
  };

  Scene3D.prototype.project = function (x, y, z) {  // CSS pixels in the canvas of a scene point (tests)
    const v = this.vp, w = v[3] * x + v[7] * y + v[11] * z + v[15];
    const nx = (v[0] * x + v[4] * y + v[8] * z + v[12]) / w, ny = (v[1] * x + v[5] * y + v[9] * z + v[13]) / w;
    return [(nx + 1) / 2 * this.canvas.clientWidth, (1 - ny) / 2 * this.canvas.clientHeight];
  };

  Scene3D.prototype.draw = function (now) {
    const gl = this.gl, c = this.canvas, loc = this.loc, sc = this.scene;
    if (!gl || c.clientWidth === 0) return;  // hidden
    const dpr = window.devicePixelRatio || 1;
    const w = Math.round(c.clientWidth * dpr), h = Math.round(c.clientHeight * dpr);
    if (c.width !== w || c.height !== h) { c.width = w; c.height = h; }
    gl.viewport(0, 0, w, h);
    gl.clearColor(SKY[0], SKY[1], SKY[2], 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    gl.useProgram(this.prog);
    const far = Math.max(1000, 4 * this.span), pose = this.cameraPose();
    this.vp = mul(perspective(55 * Math.PI / 180, w / h, Math.max(0.01, 1e-5 * far), far), lookAt(pose.eye, pose.at, [0, 0, 1]));
    gl.uniformMatrix4fv(loc.vp, false, this.vp);
    gl.uniform3fv(loc.sun, SUN);
    gl.uniform3fv(loc.sky, SKY);
    gl.uniform2f(loc.fog, 2 * this.span, 6 * this.span);  // haze well beyond the harbour, as the 3D viewer's
    const drawArrays = (item, pose4, rgb, alpha, mode) => {
      gl.uniform4fv(loc.pose, pose4);
      gl.uniform3f(loc.rgb, rgb[0] / 255, rgb[1] / 255, rgb[2] / 255);
      gl.uniform1f(loc.alpha, alpha);
      gl.bindBuffer(gl.ARRAY_BUFFER, item.pos);
      gl.enableVertexAttribArray(loc.p);
      gl.vertexAttribPointer(loc.p, 3, gl.FLOAT, false, 0, 0);
      if (item.nrm) {
        gl.bindBuffer(gl.ARRAY_BUFFER, item.nrm);
        gl.enableVertexAttribArray(loc.nrm);
        gl.vertexAttribPointer(loc.nrm, 3, gl.FLOAT, false, 0, 0);
      } else {
        gl.disableVertexAttribArray(loc.nrm);
        gl.vertexAttrib3f(loc.nrm, 0, 0, 1);
      }
      gl.drawArrays(mode === undefined ? gl.TRIANGLES : mode, 0, item.n);
    };
    const still = [0, 0, 1, 0];
    const ship = (s, hull, rgb) => {
      const hr = s.hdg * Math.PI / 180, p = [s.x, s.y, Math.cos(hr), Math.sin(hr)];
      (this.hulls[hull] || this.hulls.own).forEach((m, i) => drawArrays(m, p, i === 0 ? rgb : m.rgb, 1));
    };
    for (const m of this.harbour) if (m.alpha >= 1) drawArrays(m, still, m.rgb, 1);
    for (const r of this.rings) drawArrays(r, still, r.rgb, 1, gl.LINES);
    if (this.own) ship(this.own, "own", this.own.ended ? sc.rgb.ended : sc.rgb.own);
    for (const s of this.others) if (s.x !== null && s.hdg !== null) ship(s, s.hull, s.rgb);
    // the transparent last: the goal's area, then the sea (the bed and the slabs show through)
    gl.enable(gl.BLEND);
    gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
    gl.depthMask(false);
    for (const m of this.harbour) if (m.alpha < 1) drawArrays(m, still, m.rgb, m.alpha);
    const t = this.t + Math.min(0.5, this.tAt ? (now - this.tAt) / 1000 * this.rate : 0);
    this.sea(t);
    gl.depthMask(true);
    gl.disable(gl.BLEND);
    this.frames += 1;
  };

  // the sea surface at time t: the server's components a sin(kx x + ky y - omega t + phase), and its normal
  Scene3D.prototype.sea = function (t) {
    const gl = this.gl, loc = this.loc, sea = this.scene.sea, P = this.seaPos, N = this.seaNrm;
    const comps = sea.components;
    if (comps.length) {
      for (let i = 0; i < P.length; i += 3) {
        let z = 0, dx = 0, dy = 0;
        for (const [a, kx, ky, om, ph] of comps) {
          const arg = kx * P[i] + ky * P[i + 1] - om * t + ph;
          z += a * Math.sin(arg);
          const d = a * Math.cos(arg);
          dx += d * kx; dy += d * ky;
        }
        P[i + 2] = z;
        const l = Math.hypot(dx, dy, 1);
        N[i] = -dx / l; N[i + 1] = -dy / l; N[i + 2] = 1 / l;
      }
      gl.bindBuffer(gl.ARRAY_BUFFER, this.seaBuf);
      gl.bufferSubData(gl.ARRAY_BUFFER, 0, P);
      gl.bindBuffer(gl.ARRAY_BUFFER, this.seaNrmBuf);
      gl.bufferSubData(gl.ARRAY_BUFFER, 0, N);
    }
    gl.uniform4fv(loc.pose, [0, 0, 1, 0]);
    gl.uniform3f(loc.rgb, sea.rgb[0] / 255, sea.rgb[1] / 255, sea.rgb[2] / 255);
    gl.uniform1f(loc.alpha, sea.opacity);
    gl.bindBuffer(gl.ARRAY_BUFFER, this.seaBuf);
    gl.enableVertexAttribArray(loc.p);
    gl.vertexAttribPointer(loc.p, 3, gl.FLOAT, false, 0, 0);
    gl.bindBuffer(gl.ARRAY_BUFFER, this.seaNrmBuf);
    gl.enableVertexAttribArray(loc.nrm);
    gl.vertexAttribPointer(loc.nrm, 3, gl.FLOAT, false, 0, 0);
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.seaIdx);
    gl.drawElements(gl.TRIANGLES, this.seaN, gl.UNSIGNED_SHORT, 0);
  };

  window.Scene3D = Scene3D;
})();
