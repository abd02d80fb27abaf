// plastivox 3-D viewer: replays a packed life (docs/rendering.md, "The 3-D viewer") with
// three.js (Debian's libjs-three, inlined by the page). One viewer per page; load(i) swaps
// the life it shows. Voxels are one merged mesh of boxes (24 vertices each) rewritten per
// frame from the quantised poses; colours use the renderer's colour maps and scales, which
// the page carries (window.PLASTIVOX_COLORMAPS, each life's meta.scales). A life in an
// environment also carries its world (meta.world): the ground, drawn instead of the floor,
// and obstacle boxes.
(function () {
  "use strict";

  // ---- packed life --------------------------------------------------------------------
  function bytesOf(b64) {
    const text = atob(b64);
    const out = new Uint8Array(text.length);
    for (let i = 0; i < text.length; ++i) out[i] = text.charCodeAt(i);
    return out.buffer;
  }

  function parseLife(entry) {
    const buf = bytesOf(entry.data);
    const v = new DataView(buf);
    const magic = String.fromCharCode(v.getUint8(0), v.getUint8(1), v.getUint8(2), v.getUint8(3));
    if (magic !== "PVL1") throw new Error("not a packed plastivox life (magic " + magic + ")");
    let at = 4;
    const u32 = () => { const x = v.getUint32(at, true); at += 4; return x; };
    const f32 = () => { const x = v.getFloat32(at, true); at += 4; return x; };
    const life = { meta: entry.meta };
    life.n = u32();
    life.frames = u32();
    life.L = f32();
    life.lo = [f32(), f32(), f32()];
    life.hi = [f32(), f32(), f32()];
    life.sizeLo = f32(); life.sizeHi = f32();
    life.eLo = f32(); life.eHi = f32();
    life.stim = f32();
    const n = life.n, F = life.frames;
    life.logE0 = new Float32Array(n);
    life.phase = new Float32Array(n);
    for (let i = 0; i < n; ++i) life.logE0[i] = f32();
    for (let i = 0; i < n; ++i) life.phase[i] = f32();
    life.time = new Float32Array(F);
    life.disp = new Float32Array(F);
    life.com = new Float32Array(3 * F);
    for (let k = 0; k < F; ++k) {
      life.time[k] = f32();
      life.disp[k] = f32();
      for (let a = 0; a < 3; ++a) life.com[3 * k + a] = f32();
    }
    life.view = v;
    life.body = at;  // 13 bytes per frame and voxel from here
    // Then, when recorded, the actuation signal: 1 byte per frame and voxel.
    life.act = buf.byteLength === at + 14 * n * F ? at + 13 * n * F : -1;
    if (life.act < 0 && buf.byteLength !== at + 13 * n * F)
      throw new Error("packed life has the wrong length");
    return life;
  }

  const SQRT1_2 = Math.SQRT1_2;
  // Voxel i of frame k: centre (m), quaternion (w, x, y, z), size (m), log10 E, stimulus,
  // actuation signal (0 when not recorded).
  function voxel(life, k, i, out) {
    const v = life.view;
    let at = life.body + 13 * (k * life.n + i);
    for (let a = 0; a < 3; ++a) {
      out.p[a] = life.lo[a] + (v.getUint16(at, true) / 65535) * (life.hi[a] - life.lo[a]);
      at += 2;
    }
    const r = v.getUint32(at, true);
    at += 4;
    const big = r >>> 30;
    const c = [((r >>> 20) & 1023) / 1023 * 2 - 1, ((r >>> 10) & 1023) / 1023 * 2 - 1,
               (r & 1023) / 1023 * 2 - 1];
    let sum = 0, j = 0;
    for (let m = 0; m < 4; ++m) {
      if (m === big) continue;
      out.q[m] = c[j++] * SQRT1_2;
      sum += out.q[m] * out.q[m];
    }
    out.q[big] = Math.sqrt(Math.max(0, 1 - sum));
    out.size = life.sizeLo + v.getUint8(at) / 255 * (life.sizeHi - life.sizeLo);
    out.logE = life.eLo + v.getUint8(at + 1) / 255 * (life.eHi - life.eLo);
    out.stimulus = (v.getUint8(at + 2) / 255 * 2 - 1) * life.stim;
    out.actuation = life.act < 0 ? 0 : v.getUint8(life.act + k * life.n + i) / 255 * 2 - 1;
  }

  // ---- colours: the renderer's maps (256 sRGB entries, linear between entries) -----------
  function mapColor(name, t, out) {
    const table = window.PLASTIVOX_COLORMAPS[name];
    const x = Math.min(Math.max(t, 0), 1) * 255;
    const i = Math.min(Math.floor(x), 254), f = x - i;
    for (let c = 0; c < 3; ++c)
      out[c] = Math.round(table[3 * i + c] * (1 - f) + table[3 * (i + 1) + c] * f) / 255;
  }
  function position(mode, scale, value) {
    if (mode === "phase") return value - Math.floor(value);
    if (!isFinite(value)) return 0.5;
    return Math.min(Math.max((value - scale.lo) / (scale.hi - scale.lo), 0), 1);
  }
  function colourValue(mode, life, i, vox) {
    switch (mode) {
      case "congenital": return life.logE0[i];
      case "stiffness": return vox.logE;
      case "change": return vox.logE - life.logE0[i];
      case "stimulus": return vox.stimulus;
      case "actuation": return vox.actuation;
      case "phase": return life.phase[i];
    }
    return 0;
  }

  // ---- box geometry: 6 faces x 4 corners, local half-size 0.5 ---------------------------
  const FACES = [  // normal, then 4 corners counter-clockwise seen from outside
    [[1, 0, 0], [[1, -1, -1], [1, 1, -1], [1, 1, 1], [1, -1, 1]]],
    [[-1, 0, 0], [[-1, 1, -1], [-1, -1, -1], [-1, -1, 1], [-1, 1, 1]]],
    [[0, 1, 0], [[1, 1, -1], [-1, 1, -1], [-1, 1, 1], [1, 1, 1]]],
    [[0, -1, 0], [[-1, -1, -1], [1, -1, -1], [1, -1, 1], [-1, -1, 1]]],
    [[0, 0, 1], [[-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]]],
    [[0, 0, -1], [[-1, 1, -1], [1, 1, -1], [1, -1, -1], [-1, -1, -1]]],
  ];

  const FLOOR_POLAR_LIMIT = (89 * Math.PI) / 180;  // radians from straight down onto the target
  const FLOOR_COLOR = 0xdcdde0, OBSTACLE_COLOR = 0x968470;  // the renderer's floor and obstacles

  // Flat-shaded triangles (x, y, z per corner) as a mesh of one colour.
  function triangleMesh(corners, color) {
    const g = new THREE.BufferGeometry();
    g[g.setAttribute ? "setAttribute" : "addAttribute"](
        "position", new THREE.BufferAttribute(new Float32Array(corners), 3));
    g.computeVertexNormals();  // unindexed: each triangle's own normal
    return new THREE.Mesh(g, new THREE.MeshLambertMaterial({ color: color }));
  }

  // The ground of meta.world: heights h (x fastest) at the crossings of the lines x and y,
  // two triangles a cell, counter-clockwise seen from above.
  function groundMesh(ground) {
    const xs = ground.x, ys = ground.y, h = ground.h, nx = xs.length, out = [];
    const p = (i, j) => [xs[i], ys[j], h[i + nx * j]];
    for (let j = 0; j + 1 < ys.length; ++j)
      for (let i = 0; i + 1 < nx; ++i) {
        const a = p(i, j), b = p(i + 1, j), c = p(i + 1, j + 1), d = p(i, j + 1);
        out.push(...a, ...b, ...c, ...a, ...c, ...d);
      }
    return triangleMesh(out, FLOOR_COLOR);
  }

  // The obstacle boxes of meta.world, [min x, min y, min z, max x, max y, max z] each.
  function obstacleMesh(boxes) {
    const out = [];
    for (const b of boxes)
      for (const [, corners] of FACES) {
        const at = corners.map((c) => c.map((s, a) => (s < 0 ? b[a] : b[a + 3])));
        out.push(...at[0], ...at[1], ...at[2], ...at[0], ...at[2], ...at[3]);
      }
    return triangleMesh(out, OBSTACLE_COLOR);
  }

  function Viewer(root) {
    this.root = root;
    const q = (c) => root.querySelector("." + c);
    this.canvas = q("pv-canvas");
    this.slider = q("pv-time");
    this.playButton = q("pv-play");
    this.speedSelect = q("pv-speed");
    this.colorSelect = q("pv-color");
    this.cameraSelect = q("pv-camera");
    this.readout = q("pv-readout");
    this.colorbar = q("pv-colorbar");
    this.caption = q("pv-caption");
    this.renderer = new THREE.WebGLRenderer({ canvas: this.canvas, antialias: false,
                                              preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(1);
    this.renderer.setSize(this.canvas.clientWidth || 800, this.canvas.clientHeight || 450, false);
    this.renderer.setClearColor(0xf4f5f7);
    this.scene = new THREE.Scene();
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x505058, 0.65));
    const sun = new THREE.DirectionalLight(0xffffff, 0.55);
    sun.position.set(0.4, -0.6, 1.0);
    this.scene.add(sun);
    this.camera = new THREE.PerspectiveCamera(30, this.canvas.width / this.canvas.height, 1e-3, 1e3);
    this.camera.up.set(0, 0, 1);
    this.controls = new THREE.OrbitControls(this.camera, this.canvas);
    // The camera never goes under the floor (z = 0): it orbits no lower than a degree above
    // its target's horizon, and every update first lifts a target below the floor (a sunk
    // body followed) onto it, so the camera, above the target, is above the floor.
    this.controls.maxPolarAngle = FLOOR_POLAR_LIMIT;
    const orbitUpdate = this.controls.update;
    this.controls.update = () => { this.keepAboveFloor(); return orbitUpdate(); };
    this.controls.addEventListener("change", () => this.draw());
    this.mode = this.colorSelect ? this.colorSelect.value : "congenital";
    this.speed = 1;
    this.playing = false;
    this.frame = 0;
    this.vox = { p: [0, 0, 0], q: [1, 0, 0, 0], size: 0, logE: 0, stimulus: 0, actuation: 0 };
    const self = this;
    if (this.slider) this.slider.addEventListener("input", () => { self.pause(); self.setFrame(+self.slider.value); });
    if (this.playButton) this.playButton.addEventListener("click", () => (self.playing ? self.pause() : self.play()));
    if (this.speedSelect) this.speedSelect.addEventListener("change", () => { self.speed = +self.speedSelect.value; });
    if (this.colorSelect) this.colorSelect.addEventListener("change", () => { self.mode = self.colorSelect.value; self.drawColorbar(); self.setFrame(self.frame); });
    if (this.cameraSelect) this.cameraSelect.addEventListener("change", () => self.setFrame(self.frame));
  }

  Viewer.prototype.load = function (entry) {
    this.pause();
    const life = parseLife(entry);
    this.life = life;
    if (this.mesh) { this.scene.remove(this.mesh); this.mesh.geometry.dispose(); }
    for (const part of this.worldParts || []) {
      this.scene.remove(part);
      if (part.geometry) part.geometry.dispose();
    }
    this.worldParts = [];
    const n = life.n, L = life.L;
    const g = new THREE.BufferGeometry();
    this.positions = new Float32Array(n * 24 * 3);
    this.normals = new Float32Array(n * 24 * 3);
    this.colors = new Float32Array(n * 24 * 3);
    // Only faces on the body's surface are drawn: a face that touches a neighbour in the
    // lattice (found from frame 0, the rest pose) stays hidden inside the body while it
    // deforms, and software WebGL's time goes on fragments (a 10x10x10 cube: 600 of 6000).
    const sites = new Set(), cell = [], p0 = [0, 0, 0];
    for (let i = 0; i < n; ++i) {
      voxel(life, 0, i, this.vox);
      if (i === 0) p0.splice(0, 3, ...this.vox.p);  // sites relative to voxel 0: no ties at .5
      const c = [0, 1, 2].map((a) => Math.round((this.vox.p[a] - p0[a]) / L));
      cell.push(c);
      sites.add(c.join(","));
    }
    const faces = [];
    this.exposed = new Uint8Array(6 * n);  // setFrame skips the hidden faces' vertices too
    for (let i = 0; i < n; ++i)
      for (let f = 0; f < 6; ++f) {
        const d = FACES[f][0], c = cell[i];
        if (sites.has([c[0] + d[0], c[1] + d[1], c[2] + d[2]].join(","))) continue;
        this.exposed[6 * i + f] = 1;
        faces.push(4 * (6 * i + f));
      }
    const index = new Uint32Array(6 * faces.length);
    faces.forEach((b, j) => index.set([b, b + 1, b + 2, b, b + 2, b + 3], 6 * j));
    this.drawnFaces = faces.length;
    const set = g.setAttribute ? "setAttribute" : "addAttribute";
    g[set]("position", new THREE.BufferAttribute(this.positions, 3));
    g[set]("normal", new THREE.BufferAttribute(this.normals, 3));
    g[set]("color", new THREE.BufferAttribute(this.colors, 3));
    g.setIndex(new THREE.BufferAttribute(index, 1));
    this.mesh = new THREE.Mesh(g, new THREE.MeshLambertMaterial({ vertexColors: THREE.VertexColors }));
    this.mesh.frustumCulled = false;
    this.scene.add(this.mesh);
    // The floor: a plane under the whole life with a grid of one voxel length; or the
    // environment's ground in its place. Obstacle boxes on either.
    const world = life.meta.world;
    if (world && world.ground) {
      this.worldParts.push(groundMesh(world.ground));
    } else {
      const cx = 0.5 * (life.lo[0] + life.hi[0]), cy = 0.5 * (life.lo[1] + life.hi[1]);
      const extent = Math.max(life.hi[0] - life.lo[0], life.hi[1] - life.lo[1]) + 40 * L;
      const cells = Math.ceil(extent / L);
      const floor = new THREE.Mesh(new THREE.PlaneBufferGeometry(cells * L, cells * L),
                                   new THREE.MeshLambertMaterial({ color: FLOOR_COLOR }));
      floor.position.set(cx, cy, -1e-4 * L);
      const grid = new THREE.GridHelper(cells * L, cells, 0xb8b9be, 0xc8c9ce);
      grid.rotation.x = Math.PI / 2;
      grid.position.set(cx, cy, 0);
      this.worldParts.push(floor, grid);
    }
    if (world && world.obstacles.length) this.worldParts.push(obstacleMesh(world.obstacles));
    for (const part of this.worldParts) this.scene.add(part);
    this.floorZ = world ? world.zmin : 0;  // the camera's target stays above this level
    // Camera: azimuth -60 deg, elevation 25 deg, the body at t = 0 filling about half the
    // view (as the renderer's default framing).
    const lo0 = [Infinity, Infinity, Infinity], hi0 = [-Infinity, -Infinity, -Infinity];
    for (let i = 0; i < n; ++i) {
      voxel(life, 0, i, this.vox);
      for (let a = 0; a < 3; ++a) {
        lo0[a] = Math.min(lo0[a], this.vox.p[a]);
        hi0[a] = Math.max(hi0[a], this.vox.p[a]);
      }
    }
    const span = Math.max(hi0[0] - lo0[0], hi0[1] - lo0[1], hi0[2] - lo0[2]) + L;
    const d = 1.5 * span / Math.tan((this.camera.fov * Math.PI) / 360);
    const az = (-60 * Math.PI) / 180, el = (25 * Math.PI) / 180;
    this.offset = new THREE.Vector3(Math.cos(el) * Math.cos(az), Math.cos(el) * Math.sin(az), Math.sin(el)).multiplyScalar(d);
    this.camera.near = d / 100;
    this.camera.far = d * 100;
    this.camera.updateProjectionMatrix();
    const c0 = this.comAt(0);
    this.controls.target.copy(c0);
    this.camera.position.copy(c0).add(this.offset);
    this.controls.update();
    if (this.slider) { this.slider.max = life.frames - 1; this.slider.value = 0; }
    if (this.caption)
      this.caption.textContent = life.meta.label + " \u00b7 " + life.n + " voxels \u00b7 fitness " +
          life.meta.fitness.toFixed(4) + " voxel lengths";
    this.drawColorbar();
    this.setFrame(0);
  };

  Viewer.prototype.comAt = function (k) {
    const c = this.life.com;
    return new THREE.Vector3(c[3 * k], c[3 * k + 1], c[3 * k + 2]);
  };

  Viewer.prototype.setFrame = function (k) {
    const life = this.life;
    if (!life) return;  // a linked life still loading
    k = Math.max(0, Math.min(life.frames - 1, k | 0));
    const moved = k !== this.frame;
    this.frame = k;
    const scale = life.meta.scales[this.mode];
    const vox = this.vox, rgb = [0, 0, 0];
    const P = this.positions, N = this.normals, C = this.colors;
    for (let i = 0; i < life.n; ++i) {
      voxel(life, k, i, vox);
      const [w, x, y, z] = vox.q;
      // Rotation matrix of the unit quaternion (body to world).
      const r00 = 1 - 2 * (y * y + z * z), r01 = 2 * (x * y - w * z), r02 = 2 * (x * z + w * y);
      const r10 = 2 * (x * y + w * z), r11 = 1 - 2 * (x * x + z * z), r12 = 2 * (y * z - w * x);
      const r20 = 2 * (x * z - w * y), r21 = 2 * (y * z + w * x), r22 = 1 - 2 * (x * x + y * y);
      const h = 0.5 * vox.size;
      mapColor(scale.map, position(this.mode, scale, colourValue(this.mode, life, i, vox)), rgb);
      let at = 72 * i;
      for (let f = 0; f < 6; ++f) {
        if (!this.exposed[6 * i + f]) { at += 12; continue; }
        const [nrm, corners] = FACES[f];
        const nx = r00 * nrm[0] + r01 * nrm[1] + r02 * nrm[2];
        const ny = r10 * nrm[0] + r11 * nrm[1] + r12 * nrm[2];
        const nz = r20 * nrm[0] + r21 * nrm[1] + r22 * nrm[2];
        for (let c = 0; c < 4; ++c, at += 3) {
          const lx = h * corners[c][0], ly = h * corners[c][1], lz = h * corners[c][2];
          P[at] = vox.p[0] + r00 * lx + r01 * ly + r02 * lz;
          P[at + 1] = vox.p[1] + r10 * lx + r11 * ly + r12 * lz;
          P[at + 2] = vox.p[2] + r20 * lx + r21 * ly + r22 * lz;
          N[at] = nx; N[at + 1] = ny; N[at + 2] = nz;
          C[at] = rgb[0]; C[at + 1] = rgb[1]; C[at + 2] = rgb[2];
        }
      }
    }
    const attr = this.mesh.geometry.attributes;
    attr.position.needsUpdate = attr.normal.needsUpdate = attr.color.needsUpdate = true;
    // Follow camera: keep the view's offset from the body's centre of mass.
    if (!this.cameraSelect || this.cameraSelect.value === "follow") {
      const com = this.comAt(k);
      const delta = com.clone().sub(this.controls.target);
      this.controls.target.copy(com);
      this.camera.position.add(delta);
      this.controls.update();
    }
    if (this.slider && moved) this.slider.value = k;
    this.updateReadout();
    this.draw();
  };

  Viewer.prototype.updateReadout = function () {
    if (!this.readout) return;
    const life = this.life, k = this.frame;
    const t = life.time[k], disp = life.disp[k];
    this.readout.dataset.time = t;
    this.readout.dataset.displacement = disp;
    this.readout.dataset.frame = k;
    this.readout.textContent = "t = " + t.toFixed(2) + " s \u00b7 " + life.meta.treatment +
        " \u00b7 displacement " + disp.toFixed(3) + " voxel lengths" +
        (t < life.meta.settle_time ? " (settling)" : "");
  };

  // Lifts the target and the camera together (the view's direction kept) so the target is
  // not below the floor (or the lowest point of the world's ground and boxes); the orbit's
  // update then keeps the camera above the target.
  Viewer.prototype.keepAboveFloor = function () {
    const below = (this.floorZ || 0) - this.controls.target.z;
    if (below > 0) {
      this.controls.target.z += below;
      this.camera.position.z += below;
    }
  };

  Viewer.prototype.draw = function () { this.renderer.render(this.scene, this.camera); };

  Viewer.prototype.drawColorbar = function () {
    const cb = this.colorbar;
    if (!cb || !this.life) return;
    const scale = this.life.meta.scales[this.mode];
    const ctx = cb.getContext("2d");
    const W = cb.width, H = cb.height, x0 = 30, x1 = W - 30, y0 = 22, y1 = 38;
    ctx.clearRect(0, 0, W, H);
    const rgb = [0, 0, 0];
    for (let x = x0; x < x1; ++x) {
      mapColor(scale.map, (x - x0) / (x1 - x0 - 1), rgb);
      ctx.fillStyle = "rgb(" + rgb.map((c) => Math.round(255 * c)).join(",") + ")";
      ctx.fillRect(x, y0, 1, y1 - y0);
    }
    ctx.fillStyle = "#222";
    ctx.font = "12px sans-serif";
    ctx.textAlign = "left";
    ctx.fillText(scale.title, x0, 14);
    ctx.textAlign = "center";
    for (const tick of scale.ticks) {
      const x = x0 + tick.t * (x1 - x0);
      ctx.fillRect(x, y1, 1, 4);
      ctx.fillText(tick.label, x, y1 + 16);
    }
  };

  Viewer.prototype.play = function () {
    if (!this.life || this.playing) return;
    if (this.frame >= this.life.frames - 1) this.setFrame(0);
    this.playing = true;
    if (this.playButton) this.playButton.textContent = "pause";
    let last = performance.now(), t = this.life.time[this.frame];
    const step = (now) => {
      if (!this.playing) return;
      t += ((now - last) / 1000) * this.speed;
      last = now;
      const times = this.life.time;
      let k = this.frame;
      while (k + 1 < times.length && times[k + 1] <= t) ++k;
      if (k !== this.frame) this.setFrame(k);
      if (k >= times.length - 1) { this.pause(); return; }
      requestAnimationFrame(step);
    };
    requestAnimationFrame(step);
  };

  Viewer.prototype.pause = function () {
    this.playing = false;
    if (this.playButton) this.playButton.textContent = "play";
  };

  // The canvas as RGBA bytes (rows bottom-up, as WebGL reads them), for tests.
  Viewer.prototype.pixels = function () {
    const gl = this.renderer.getContext();
    const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
    const out = new Uint8Array(4 * w * h);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, out);
    return out;
  };

  window.plastivoxViewer = {
    viewer: null,
    // Voxel i of frame k of the life shown, decoded (tests compare it with the recording).
    decode: function (k, i) {
      const out = { p: [0, 0, 0], q: [1, 0, 0, 0], size: 0, logE: 0, stimulus: 0, actuation: 0 };
      voxel(this.viewer.life, k, i, out);
      return out;
    },
    // Starts the viewer in `root` (the element holding the canvas and controls) on life i of
    // window.PLASTIVOX_LIVES.
    start: function (root, i) {
      document.querySelectorAll("[data-pv-life]").forEach((b) => {
        b.textContent = window.PLASTIVOX_LIVES[+b.dataset.pvLife].meta.label;
      });
      this.viewer = new Viewer(root);
      this.load(i);
      return this.viewer;
    },
    // Shows life i. A life a report links rather than embeds ({id, src}) is loaded from its
    // script on first use; the script calls deliver() below.
    load: function (i) {
      const entry = window.PLASTIVOX_LIVES[i];
      this.current = i;
      document.querySelectorAll("[data-pv-life]").forEach((b) =>
        b.classList.toggle("pv-current", +b.dataset.pvLife === i));
      if (entry.data) { this.viewer.load(entry); return; }
      if (this.viewer.caption) this.viewer.caption.textContent = "loading " + entry.src + " \u2026";
      if (entry.requested) return;
      entry.requested = true;
      const script = document.createElement("script");
      script.src = entry.src;
      script.onerror = () => {
        entry.requested = false;
        if (this.viewer.caption) this.viewer.caption.textContent = "could not load " + entry.src;
      };
      document.head.appendChild(script);
    },
    // Called by a linked life's script with its packed bytes and meta.
    deliver: function (id, life) {
      const i = window.PLASTIVOX_LIVES.findIndex((e) => e.id === id);
      if (i < 0) return;
      Object.assign(window.PLASTIVOX_LIVES[i], life);
      if (this.current === i) this.load(i);
    },
  };
})();
