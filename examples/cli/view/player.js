// The player of the pages `anima view` writes (examples/cli/view_page.cpp
// puts it into examples/cli/view/player.html with the clips' data). The CLI
// has computed every joint's position in every frame (millimetres; x the
// figure's left, y up, z its front); this script only places the clips,
// keeps them in sync and draws them: with three.js (embedded in the page,
// loaded from a blob URL, no network) when the browser has WebGL 2, else
// with a 2D canvas. Its state is on <body> for automated checks:
// data-renderer, data-frames, data-frame, data-clips, data-markers, and
// data-played (seconds played so far). It logs nothing to the console.
(function () {
  'use strict';

  const body = document.body;
  const data = JSON.parse(document.getElementById('anima-data').textContent);
  const stage = document.getElementById('stage');
  const timeline = document.getElementById('timeline');
  const slider = document.getElementById('slider');
  const clock = document.getElementById('clock');
  const playButton = document.getElementById('play');
  const speedSelect = document.getElementById('speed');
  const followBox = document.getElementById('follow');
  const overlayBox = document.getElementById('overlay');

  const SIDE_COLOURS = ['#3a3a3a', '#1f63c6', '#d0342c'];  // centre, left, right (anima::body_side)
  const CLIP_COLOURS = ['#3a3a3a', '#e07b00', '#2a9d5c', '#7b4fc9', '#c03a7a', '#1b8fb0'];
  const CONTACT_COLOUR = '#1fae4b';
  const TARGET_COLOUR = '#e0202a';
  const MARKER_COLOURS = {
    seam: '#d62728', overlap: '#ff9f1c', transition: '#7b4fc9', turn: '#1f63c6', jump: '#1b8fb0', key: '#2a9d5c',
    target: '#e0202a', m1: '#28a046', m2: '#285ac8'
  };

  // --- the clips ------------------------------------------------------------
  const clips = data.clips.map(function (c, index) {
    const positions = new Float32Array(c.positions.length);
    for (let i = 0; i < positions.length; ++i) positions[i] = c.positions[i] / 1000;
    const feet = c.feet.map(function (foot) {
      const on = new Uint8Array(c.frames);
      for (const run of foot.runs) on.fill(1, run[0], run[1] + 1);
      return { name: foot.name, points: foot.points, runs: foot.runs, on: on };
    });
    // The clip's extent across (x) over all frames, to place clips side by side.
    let xmin = Infinity, xmax = -Infinity;
    for (let i = 0; i < positions.length; i += 3) {
      xmin = Math.min(xmin, positions[i]);
      xmax = Math.max(xmax, positions[i]);
    }
    return {
      index: index, label: c.label, frames: c.frames, dt: c.frame_time, points: c.points, bones: c.bones,
      feet: feet, positions: positions, xmin: xmin, xmax: xmax, offset: [0, 0, 0],
      duration: c.frames * c.frame_time,
      targets: data.targets.filter(function (t) { return t.clip === index; })
    };
  });
  const first = clips[0];
  const duration = Math.max.apply(null, clips.map(function (c) { return c.duration; }));
  const steps = Math.max(1, Math.round(duration / first.dt));  // slider positions, in the first clip's frames

  body.dataset.frames = String(first.frames);
  body.dataset.clips = String(clips.length);
  body.dataset.markers = String(data.markers.length);

  let overlay = !!data.overlay;
  overlayBox.checked = overlay;
  overlayBox.disabled = clips.length < 2;

  /// Side by side: one lane across (x) per clip, each starting where the
  /// others do. Overlaid: where the files put them (a transition and its
  /// input line up).
  function placeClips() {
    const widest = Math.max.apply(null, clips.map(function (c) { return c.xmax - c.xmin; }));
    const spacing = Math.max(1, widest + 0.6);
    clips.forEach(function (c, k) {
      const x0 = c.positions[0], z0 = c.positions[2];
      c.offset = overlay ? [0, 0, 0] : [(k - (clips.length - 1) / 2) * spacing - x0, 0, -z0];
    });
    return spacing;
  }

  function frameOf(c, t) { return Math.max(0, Math.min(c.frames - 1, Math.floor(t / c.dt + 1e-6))); }

  /// Point p of clip c at frame f, placed on the page.
  function point(c, f, p) {
    const i = (f * c.points + p) * 3;
    return [c.positions[i] + c.offset[0], c.positions[i + 1] + c.offset[1], c.positions[i + 2] + c.offset[2]];
  }

  function clipColour(c) { return overlay && clips.length > 1 ? CLIP_COLOURS[c.index % CLIP_COLOURS.length] : null; }

  // --- legend ---------------------------------------------------------------
  function buildLegend() {
    const legend = document.getElementById('legend');
    legend.textContent = '';
    const h = document.createElement('h1');
    h.textContent = data.title;
    legend.appendChild(h);
    const line = document.createElement('div');
    clips.forEach(function (c, k) {
      const swatch = document.createElement('span');
      swatch.className = 'swatch';
      swatch.style.background = clipColour(c) || SIDE_COLOURS[0];
      if (k === 0) swatch.style.marginLeft = '0';
      line.appendChild(swatch);
      line.appendChild(document.createTextNode(c.label + (overlay ? '' : k === 0 ? ' (left)' : k === clips.length - 1 ? ' (right)' : '')));
    });
    const contact = document.createElement('span');
    contact.className = 'swatch';
    contact.style.background = CONTACT_COLOUR;
    line.appendChild(contact);
    line.appendChild(document.createTextNode('foot planted'));
    legend.appendChild(line);
    if (!overlay) {
      const sides = document.createElement('div');
      sides.style.color = '#555';
      sides.textContent = 'blue: left side, red: right side';
      legend.appendChild(sides);
    }
  }
  buildLegend();

  // --- camera: orbit about a target (both renderers) ------------------------
  const camera = { target: [0, 0.9, 0], azimuth: 0.55, elevation: 0.22, distance: 4, fov: 45, fit: 0 };
  function fitCamera() {
    const span = overlay ? 1.5 : clips.length * placeClips();
    camera.distance = Math.max(3.5, 1.2 * span + 1.5);
  }
  fitCamera();
  function eye() {
    const ce = Math.cos(camera.elevation), r = Math.max(camera.distance, camera.fit);
    return [camera.target[0] + r * Math.sin(camera.azimuth) * ce,
            camera.target[1] + r * Math.sin(camera.elevation),
            camera.target[2] + r * Math.cos(camera.azimuth) * ce];
  }
  /// Aims at the middle of the clips' roots (height kept) and stands back
  /// far enough to see them all when they have drifted apart.
  function follow(frames) {
    let x0 = Infinity, x1 = -Infinity, z0 = Infinity, z1 = -Infinity;
    clips.forEach(function (c, k) {
      const p = point(c, frames[k], 0);
      x0 = Math.min(x0, p[0]);
      x1 = Math.max(x1, p[0]);
      z0 = Math.min(z0, p[2]);
      z1 = Math.max(z1, p[2]);
    });
    camera.target[0] = (x0 + x1) / 2;
    camera.target[2] = (z0 + z1) / 2;
    camera.fit = 1.3 * Math.hypot(x1 - x0, z1 - z0) + 2;
  }

  // --- playback state -------------------------------------------------------
  let time = 0, played = 0, playing = true, speed = 1;
  slider.max = String(steps - 1);

  function setTime(t) {
    time = ((t % duration) + duration) % duration;
  }
  function pause(p) {
    playing = !p;
    playButton.textContent = playing ? 'Pause' : 'Play';
  }
  playButton.addEventListener('click', function () { pause(playing); draw(); });
  speedSelect.addEventListener('change', function () { speed = Number(speedSelect.value); });
  followBox.addEventListener('change', function () { camera.fit = 0; draw(); });
  overlayBox.addEventListener('change', function () {
    overlay = overlayBox.checked;
    fitCamera();  // places the clips too
    buildLegend();
    renderer.restyle();
    draw();
  });
  slider.addEventListener('input', function () {
    pause(true);
    setTime(Number(slider.value) * first.dt);
    draw();
  });
  document.addEventListener('keydown', function (e) {
    if (e.target && e.target.tagName === 'SELECT') return;
    if (e.key === ' ') { pause(playing); e.preventDefault(); }
    else if (e.key === 'ArrowRight' || e.key === 'ArrowLeft') {
      pause(true);
      setTime((frameOf(first, time) + (e.key === 'ArrowRight' ? 1 : -1)) * first.dt + 1e-9);
      e.preventDefault();
    } else return;
    draw();
  });

  // Orbit, pan and zoom with the mouse (or a finger).
  let drag = null;
  stage.addEventListener('contextmenu', function (e) { e.preventDefault(); });
  stage.addEventListener('pointerdown', function (e) {
    drag = { x: e.clientX, y: e.clientY, pan: e.shiftKey || e.button === 2 };
    stage.setPointerCapture(e.pointerId);
  });
  stage.addEventListener('pointerup', function () { drag = null; });
  stage.addEventListener('pointermove', function (e) {
    if (!drag) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag.x = e.clientX;
    drag.y = e.clientY;
    if (drag.pan) {
      followBox.checked = false;
      camera.fit = 0;
      const s = camera.distance * 0.0015;
      const ca = Math.cos(camera.azimuth), sa = Math.sin(camera.azimuth);
      camera.target[0] -= (dx * ca) * s;
      camera.target[2] -= (-dx * sa) * s;
      camera.target[1] = Math.max(0, camera.target[1] + dy * s);
    } else {
      camera.azimuth -= dx * 0.008;
      camera.elevation = Math.max(-0.05, Math.min(1.5, camera.elevation + dy * 0.008));
    }
    draw();
  });
  stage.addEventListener('wheel', function (e) {
    camera.distance = Math.max(0.5, Math.min(300, camera.distance * Math.exp(e.deltaY * 0.001)));
    e.preventDefault();
    draw();
  }, { passive: false });

  // --- the timeline: contacts per clip, markers, the playhead ---------------
  const TL = { left: 112, right: 12, top: 6, row: 14 };
  function timelineX(t, w) { return TL.left + (w - TL.left - TL.right) * t / duration; }
  function drawTimeline() {
    const ratio = window.devicePixelRatio || 1;
    const w = timeline.clientWidth, h = timeline.clientHeight;
    if (timeline.width !== Math.round(w * ratio) || timeline.height !== Math.round(h * ratio)) {
      timeline.width = Math.round(w * ratio);
      timeline.height = Math.round(h * ratio);
    }
    const g = timeline.getContext('2d');
    g.setTransform(ratio, 0, 0, ratio, 0, 0);
    g.clearRect(0, 0, w, h);
    g.font = '11px system-ui, sans-serif';
    g.textBaseline = 'middle';
    // One row per clip: its feet's contacts as thin bars.
    clips.forEach(function (c, k) {
      const y = TL.top + k * TL.row;
      g.fillStyle = '#444';
      g.textAlign = 'right';
      g.fillText(c.label.length > 15 ? c.label.slice(0, 14) + '…' : c.label, TL.left - 6, y + TL.row / 2);
      g.fillStyle = '#eee';
      g.fillRect(TL.left, y + 2, timelineX(c.duration, w) - TL.left, TL.row - 4);
      const bar = (TL.row - 4) / Math.max(1, c.feet.length);
      c.feet.forEach(function (foot, i) {
        g.fillStyle = CONTACT_COLOUR;
        for (const run of foot.runs) {
          const x0 = timelineX(run[0] * c.dt, w), x1 = timelineX((run[1] + 1) * c.dt, w);
          g.fillRect(x0, y + 2 + i * bar, Math.max(1, x1 - x0), Math.max(1, bar - 1));
        }
      });
    });
    // Markers: spans shaded, single frames as ticks, under the rows.
    const markTop = TL.top + clips.length * TL.row + 2, markBottom = h - 16;
    for (const m of data.markers) {
      const c = clips[m.clip];
      const x0 = timelineX(m.first * c.dt, w), x1 = timelineX((m.last + 1) * c.dt, w);
      const colour = MARKER_COLOURS[m.kind] || '#555';
      if (m.last > m.first) {
        g.globalAlpha = 0.35;
        g.fillStyle = colour;
        g.fillRect(x0, markTop, Math.max(1, x1 - x0), markBottom - markTop);
        g.globalAlpha = 1;
      }
      g.fillStyle = colour;
      g.fillRect(x0, markTop, 1.5, markBottom - markTop);
    }
    // Time axis.
    g.fillStyle = '#666';
    g.textAlign = 'center';
    const tick = duration > 40 ? 10 : duration > 16 ? 5 : duration > 6 ? 2 : duration > 2.5 ? 0.5 : 0.25;
    for (let t = 0; t <= duration + 1e-9; t += tick) {
      const x = timelineX(t, w);
      g.fillRect(x, markBottom, 1, 3);
      g.fillText(String(Math.round(t * 100) / 100), x, h - 7);
    }
    g.textAlign = 'right';
    g.fillText('time (s)', TL.left - 6, h - 7);
    // Kinds of markers present.
    const kinds = Array.from(new Set(data.markers.map(function (m) { return m.kind; })));
    g.textAlign = 'left';
    const lx = 8;
    kinds.forEach(function (kind, i) {
      const y = markTop + 5 + i * 11;
      if (y > markBottom) return;
      g.fillStyle = MARKER_COLOURS[kind] || '#555';
      g.fillRect(lx, y - 4, 8, 8);
      g.fillStyle = '#444';
      g.fillText(kind, lx + 11, y);
    });
    // The playhead.
    const x = timelineX(time, w);
    g.fillStyle = '#111';
    g.fillRect(x - 1, 0, 2, h - 14);
  }
  let scrubbing = false;
  function seek(e) {
    const r = timeline.getBoundingClientRect();
    const t = (e.clientX - r.left - TL.left) / (r.width - TL.left - TL.right) * duration;
    pause(true);
    setTime(Math.max(0, Math.min(duration - 1e-6, t)));
    draw();
  }
  timeline.addEventListener('pointerdown', function (e) { scrubbing = true; timeline.setPointerCapture(e.pointerId); seek(e); });
  timeline.addEventListener('pointermove', function (e) {
    if (scrubbing) { seek(e); return; }
    // The marker under the pointer, as the tooltip.
    const r = timeline.getBoundingClientRect();
    const t = (e.clientX - r.left - TL.left) / (r.width - TL.left - TL.right) * duration;
    let best = null, bestDistance = 4 / (r.width - TL.left - TL.right) * duration;
    for (const m of data.markers) {
      const c = clips[m.clip];
      const d = t < m.first * c.dt ? m.first * c.dt - t : t > (m.last + 1) * c.dt ? t - (m.last + 1) * c.dt : 0;
      if (d <= bestDistance) { best = m; bestDistance = d; }
    }
    timeline.title = best ? best.kind + ': ' + best.label : 'Click or drag to move to a frame';
  });
  timeline.addEventListener('pointerup', function () { scrubbing = false; });

  // --- renderers ------------------------------------------------------------
  /// Whether bone or point is part of a planted foot, per clip and frame.
  function plantedPoints(c, f) {
    const planted = new Set();
    for (const foot of c.feet) if (foot.on[f]) for (const p of foot.points) planted.add(p);
    return planted;
  }
  function boneColour(c, bone) { return clipColour(c) || SIDE_COLOURS[bone[2]] || SIDE_COLOURS[0]; }

  /// WebGL 2 through three.js: cylinders and spheres per clip (instanced),
  /// a grid that follows the camera, rings under planted feet.
  function makeThreeRenderer(THREE, canvas, gl) {
    const r = new THREE.WebGLRenderer({ canvas: canvas, context: gl, antialias: true });
    r.setPixelRatio(window.devicePixelRatio || 1);
    const scene = new THREE.Scene();
    scene.background = new THREE.Color('#f3f3f1');
    scene.add(new THREE.HemisphereLight(0xffffff, 0x8a8a80, 2.2));
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(3, 6, 4);
    scene.add(sun);
    // The grid in 1 m pieces, not whole lines: a line that crosses the near
    // plane is dropped by some software rasterisers (SwiftShader).
    const grid = new THREE.Group();
    const gridLines = [[], []];  // the lines through the centre, the others
    for (let k = -20; k <= 20; ++k)
      for (let i = -20; i < 20; ++i) {
        const lines = gridLines[k === 0 ? 0 : 1];
        lines.push(k, 0, i, k, 0, i + 1, i, 0, k, i + 1, 0, k);
      }
    [0x8c8c84, 0xc0c0b8].forEach(function (colour, i) {
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.Float32BufferAttribute(gridLines[i], 3));
      grid.add(new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color: colour })));
    });
    scene.add(grid);
    const cam = new THREE.PerspectiveCamera(camera.fov, 1, 0.05, 1000);
    const cylinder = new THREE.CylinderGeometry(1, 1, 1, 10);
    const sphere = new THREE.SphereGeometry(1, 12, 8);
    const ring = new THREE.RingGeometry(0.06, 0.09, 24).rotateX(-Math.PI / 2);
    const up = new THREE.Vector3(0, 1, 0), a = new THREE.Vector3(), b = new THREE.Vector3(), d = new THREE.Vector3();
    const q = new THREE.Quaternion(), s = new THREE.Vector3(), m = new THREE.Matrix4();
    const colour = new THREE.Color();
    const plantedColour = new THREE.Color(CONTACT_COLOUR);
    const parts = clips.map(function (c) {
      const material = new THREE.MeshStandardMaterial({ roughness: 0.6, metalness: 0.0, transparent: true });
      const bones = new THREE.InstancedMesh(cylinder, material, c.bones.length);
      const joints = new THREE.InstancedMesh(sphere, material.clone(), c.points);
      const rings = c.feet.map(function () {
        const mesh = new THREE.Mesh(ring, new THREE.MeshBasicMaterial({ color: CONTACT_COLOUR, side: THREE.DoubleSide }));
        scene.add(mesh);
        return mesh;
      });
      const targets = c.targets.map(function () {
        const mesh = new THREE.Mesh(new THREE.OctahedronGeometry(0.05), new THREE.MeshBasicMaterial({ color: TARGET_COLOUR }));
        scene.add(mesh);
        return mesh;
      });
      scene.add(bones);
      scene.add(joints);
      return { bones: bones, joints: joints, rings: rings, targets: targets };
    });
    function restyle() {
      clips.forEach(function (c, k) {
        const translucent = overlay && k > 0;
        parts[k].bones.material.opacity = parts[k].joints.material.opacity = translucent ? 0.75 : 1;
      });
    }
    restyle();
    return {
      name: 'webgl',
      describe: 'WebGL · three.js ' + data.three,
      restyle: restyle,
      draw: function (frames) {
        const w = stage.clientWidth, h = stage.clientHeight;
        const size = r.getSize(new THREE.Vector2());
        if (size.x !== w || size.y !== h) r.setSize(w, h, false);
        cam.aspect = w / Math.max(1, h);
        cam.updateProjectionMatrix();
        const e = eye();
        cam.position.set(e[0], e[1], e[2]);
        cam.lookAt(camera.target[0], camera.target[1], camera.target[2]);
        grid.position.set(Math.round(camera.target[0]), 0, Math.round(camera.target[2]));
        clips.forEach(function (c, k) {
          const f = frames[k], part = parts[k];
          const planted = plantedPoints(c, f);
          c.bones.forEach(function (bone, i) {
            a.fromArray(point(c, f, bone[0]));
            b.fromArray(point(c, f, bone[1]));
            d.subVectors(b, a);
            const length = d.length();
            q.setFromUnitVectors(up, length > 1e-9 ? d.divideScalar(length) : up);
            s.set(0.014, Math.max(length, 1e-6), 0.014);
            m.compose(a.add(b).multiplyScalar(0.5), q, s);
            part.bones.setMatrixAt(i, m);
            colour.set(planted.has(bone[1]) && planted.has(bone[0]) ? CONTACT_COLOUR : boneColour(c, bone));
            part.bones.setColorAt(i, colour);
          });
          for (let p = 0; p < c.points; ++p) {
            a.fromArray(point(c, f, p));
            const radius = planted.has(p) ? 0.03 : 0.017;
            m.compose(a, q.identity(), s.set(radius, radius, radius));
            part.joints.setMatrixAt(p, m);
            part.joints.setColorAt(p, planted.has(p) ? plantedColour : colour.set(clipColour(c) || '#555555'));
          }
          part.bones.instanceMatrix.needsUpdate = part.joints.instanceMatrix.needsUpdate = true;
          part.bones.instanceColor.needsUpdate = part.joints.instanceColor.needsUpdate = true;
          c.feet.forEach(function (foot, i) {
            const p = point(c, f, foot.points[0]);
            part.rings[i].visible = !!foot.on[f];
            part.rings[i].position.set(p[0], 0.002, p[2]);
          });
          c.targets.forEach(function (t, i) {
            part.targets[i].visible = t.frame === f;
            part.targets[i].position.set(t.position[0] / 1000 + c.offset[0], t.position[1] / 1000, t.position[2] / 1000 + c.offset[2]);
          });
        });
        r.render(scene, cam);
      }
    };
  }

  /// A 2D canvas: the same camera, projected by hand; far bones first.
  function makeCanvasRenderer(canvas) {
    const g = canvas.getContext('2d');
    return {
      name: 'canvas',
      describe: '2D canvas',
      restyle: function () {},
      draw: function (frames) {
        const ratio = window.devicePixelRatio || 1;
        const w = stage.clientWidth, h = stage.clientHeight;
        if (canvas.width !== Math.round(w * ratio) || canvas.height !== Math.round(h * ratio)) {
          canvas.width = Math.round(w * ratio);
          canvas.height = Math.round(h * ratio);
        }
        g.setTransform(ratio, 0, 0, ratio, 0, 0);
        g.fillStyle = '#f3f3f1';
        g.fillRect(0, 0, w, h);
        const e = eye(), t = camera.target;
        const fwd = normalise([t[0] - e[0], t[1] - e[1], t[2] - e[2]]);
        const right = normalise(cross(fwd, [0, 1, 0]));
        const upv = cross(right, fwd);
        const focal = (h / 2) / Math.tan(camera.fov * Math.PI / 360);
        const near = 0.05;
        function toCamera(p) {
          const v = [p[0] - e[0], p[1] - e[1], p[2] - e[2]];
          return [dot(v, right), dot(v, upv), dot(v, fwd)];
        }
        function toScreen(c) { return [w / 2 + focal * c[0] / c[2], h / 2 - focal * c[1] / c[2], c[2]]; }
        function project(p) {
          const c = toCamera(p);
          return c[2] > near ? toScreen(c) : null;
        }
        /// A line, cut where it passes behind the camera.
        function segment(p, q, colour, width) {
          let a = toCamera(p), b = toCamera(q);
          if (a[2] <= near && b[2] <= near) return;
          if (a[2] <= near || b[2] <= near) {
            const u = (near - a[2]) / (b[2] - a[2]);
            const cut = [a[0] + u * (b[0] - a[0]), a[1] + u * (b[1] - a[1]), near];
            if (a[2] <= near) a = cut; else b = cut;
          }
          const sa = toScreen(a), sb = toScreen(b);
          g.strokeStyle = colour;
          g.lineWidth = width;
          g.beginPath();
          g.moveTo(sa[0], sa[1]);
          g.lineTo(sb[0], sb[1]);
          g.stroke();
        }
        // The ground grid, 1 m squares around the target.
        const gx = Math.round(t[0]), gz = Math.round(t[2]);
        for (let k = -15; k <= 15; ++k) {
          const colour = k === 0 ? '#8c8c84' : '#c4c4bc';
          segment([gx + k, 0, gz - 15], [gx + k, 0, gz + 15], colour, 1);
          segment([gx - 15, 0, gz + k], [gx + 15, 0, gz + k], colour, 1);
        }
        const items = [];
        clips.forEach(function (c, k) {
          const f = frames[k];
          const planted = plantedPoints(c, f);
          const alpha = overlay && k > 0 ? 0.75 : 1;
          for (const foot of c.feet) {
            if (!foot.on[f]) continue;
            const p = point(c, f, foot.points[0]), centre = project([p[0], 0, p[2]]);
            if (centre) items.push({ z: centre[2] + 100, ring: centre, alpha: 1 });
          }
          for (const bone of c.bones) {
            const p = point(c, f, bone[0]), q = point(c, f, bone[1]);
            const a = project(p), b = project(q);
            if (!a || !b) continue;
            const both = planted.has(bone[0]) && planted.has(bone[1]);
            items.push({ z: (a[2] + b[2]) / 2, a: a, b: b, colour: both ? CONTACT_COLOUR : boneColour(c, bone), alpha: alpha });
          }
          for (const target of c.targets) {
            if (target.frame !== f) continue;
            const p = project([target.position[0] / 1000 + c.offset[0], target.position[1] / 1000, target.position[2] / 1000 + c.offset[2]]);
            if (p) items.push({ z: p[2], target: p, alpha: 1 });
          }
        });
        items.sort(function (x, y) { return y.z - x.z; });
        g.lineCap = 'round';
        for (const it of items) {
          g.globalAlpha = it.alpha;
          if (it.ring) {
            g.strokeStyle = CONTACT_COLOUR;
            g.lineWidth = 2;
            g.beginPath();
            g.ellipse(it.ring[0], it.ring[1], focal * 0.08 / it.ring[2], focal * 0.03 / it.ring[2], 0, 0, 2 * Math.PI);
            g.stroke();
          } else if (it.target) {
            const s = Math.max(3, focal * 0.05 / it.z);
            g.strokeStyle = TARGET_COLOUR;
            g.lineWidth = 2;
            g.beginPath();
            g.moveTo(it.target[0] - s, it.target[1] - s);
            g.lineTo(it.target[0] + s, it.target[1] + s);
            g.moveTo(it.target[0] - s, it.target[1] + s);
            g.lineTo(it.target[0] + s, it.target[1] - s);
            g.stroke();
          } else {
            g.strokeStyle = it.colour;
            g.lineWidth = Math.max(1.5, Math.min(8, focal * 0.035 / it.z));
            g.beginPath();
            g.moveTo(it.a[0], it.a[1]);
            g.lineTo(it.b[0], it.b[1]);
            g.stroke();
          }
        }
        g.globalAlpha = 1;
      }
    };
  }
  function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
  function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
  function normalise(a) { const n = Math.hypot(a[0], a[1], a[2]) || 1; return [a[0] / n, a[1] / n, a[2] / n]; }

  // --- drawing and the clock ------------------------------------------------
  let renderer = null;
  function draw() {
    if (!renderer) return;
    const frames = clips.map(function (c) { return frameOf(c, time); });
    if (followBox.checked) follow(frames);
    renderer.draw(frames);
    drawTimeline();
    const f = frames[0];
    slider.value = String(Math.min(steps - 1, Math.round(time / first.dt)));
    clock.textContent = 'frame ' + f + ' / ' + (first.frames - 1) + ' · ' + time.toFixed(2) + ' s';
    body.dataset.frame = String(f);
    body.dataset.played = played.toFixed(3);
  }

  let last = null, lastTick = 0;
  function tick() {
    const now = performance.now();
    if (last !== null && playing) {
      const step = Math.min(0.25, (now - last) / 1000) * speed;
      played += step;
      setTime(time + step);
    }
    last = now;
    lastTick = now;
    draw();
  }
  function animate() {
    tick();
    window.requestAnimationFrame(animate);
  }

  function note(text) { document.getElementById('note').textContent = text; }

  /// three.js from the page (a module, imported from a blob URL), or null.
  async function loadThree() {
    const source = document.getElementById('anima-three').textContent;
    if (!source.trim()) return null;
    const url = URL.createObjectURL(new Blob([source], { type: 'text/javascript' }));
    try {
      return await import(url);
    } catch (error) {
      note('three.js did not load (' + error.message + '): drawing with a 2D canvas');
      return null;
    } finally {
      URL.revokeObjectURL(url);
    }
  }

  async function start() {
    const canvas = document.createElement('canvas');
    stage.insertBefore(canvas, stage.firstChild);
    const THREE = await loadThree();
    // three.js needs WebGL 2; asking first keeps a browser without it quiet.
    let gl = null;
    if (THREE) {
      try { gl = canvas.getContext('webgl2', { antialias: true }); } catch (error) { gl = null; }
      if (!gl) note('no WebGL 2 in this browser: drawing with a 2D canvas');
    } else if (!data.three) {
      note('this page was written without three.js: drawing with a 2D canvas');
    }
    renderer = gl ? makeThreeRenderer(THREE, canvas, gl) : makeCanvasRenderer(canvas);
    body.dataset.renderer = renderer.name;
    document.getElementById('renderer').textContent = renderer.describe;
    window.addEventListener('resize', draw);
    animate();
    // requestAnimationFrame stops in hidden tabs and headless browsers: a
    // timer keeps the clock going (and the frame on screen) when it does.
    window.setInterval(function () { if (performance.now() - lastTick > 200) tick(); }, 100);
  }
  start().catch(function (error) {
    body.dataset.error = String(error && error.message || error);
    note('the player stopped: ' + body.dataset.error);
  });
})();
