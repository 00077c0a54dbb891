// The page of a model (lagrangian page): live simulation, drawing, controls, typeset solution.
//
// This file is appended to the generated ES module of the model (lagrangian.codegen's
// JavaScript target plus the page's routines scene, observables and variational; see
// lagrangian/output/page_content.py) and is called once with the model's document (the JSON
// of the page, read with textContent: every text of the model is data) and those functions.
//
// The integrators are in integrators.js (lagrangianIntegrators), the plots in plots.js.
//
// window.lagrangian, the hook for scripts and tests:
//   parameters            {name: value} of every parameter (a copy; inputs in `inputs`)
//   state()               {t, q: {name: value}, q_dot: {name: value}}
//   set(name, value)      a parameter, an input (held constant), or an initial value
//                         (theta1, theta1_dot); the motion
//                         restarts from the initial state at t = 0
//   run(t_end)            advances synchronously to t_end (from t = 0 again if t_end is
//                         behind), at the page's accuracy; returns state()
//   energy()              the energy function h = q' dL/dq' - L now
//   conserved()           {name: value} of the conserved quantities the analysis found
//   results()             [{verdict, omega_squared}] of each equilibrium at the parameters now
//   tracks(), rods()      the hoops and rails drawn now ({particle, points}), the rods' ends
//   link()                the share link of the run now (pauses it; share.js), embedded()
//   section               the Poincaré section panel: configure, fromRun, launch (section.js)
//   reset(), play(), pause(), stats() -> {fps, frame_ms, steps, steps_per_second, method}
//   screenPosition(particle) [x, y] of a particle on the mechanism's canvas (CSS pixels)
// A model that cannot run (unspecified functions) has the solution only, and the hook
// {unavailable: why}.
function lagrangianPage(model, code) {
  "use strict";
  // the equilibria and modes with their numbers at the parameters of the moment (results.js)
  const results = lagrangianResults(code && code.results, element, typesetMath);
  if (code === null) {
    // a model that cannot run here (unspecified functions): the solution and why
    document.title = model.name;
    document.getElementById("title").textContent = model.name;
    document.getElementById("description").textContent = model.description;
    document.getElementById("live").append(element("p", { class: "error" }, model.unavailable));
    typeset();
    results.update(null);
    results.fit(document.getElementById("solution"));
    window.lagrangian = Object.freeze({ unavailable: model.unavailable, results: results.now });
    return;
  }
  const n = model.coordinates.length;
  const names = model.coordinates.map((c) => c.name);
  const rates = model.coordinates.map((c) => c.velocity);
  const parameterNames = model.parameters.map((p) => p.name);
  const params = model.parameters.map((p) => p.value);
  const inputNames = model.inputs.map((u) => u.name);
  const inputs = model.inputs.map((u) => u.value); // held constant, as simulate --set F=...
  const initial = Object.assign({}, model.initial);
  const scene = model.scene;
  const RTOL = 1e-12;
  const ATOL = 1e-12;
  const PROBE_RTOL = 1e-6;
  const MAX_HISTORY = 6000;
  const WORK_BUDGET_MS = 30;
  const PANEL_MS = 250;
  const PLOT_POINTS = 600;

  // -- numbers -------------------------------------------------------------------------
  const flat = (rows) => rows.map((row) => (Array.isArray(row) ? row[0] : row));
  const initialState = () => [...names.map((q) => initial[q]), ...rates.map((v) => initial[v])];
  const derivative = (t, y) => code.rhs(t, y, params, inputs);

  // -- the integrators (integrators.js) -------------------------------------------------
  const variationalAvailable = model.constraints === 0;
  const integrators = lagrangianIntegrators(model.dop853, n, model.t_end, {
    derivative,
    momentaAndForces: (t, y) => code.variational(t, y, params, inputs).map(flat),
    massMatrix: (t, y) => code.mass_matrix(t, y, params, inputs),
    solve: code.solve,
  });

  // -- the run ---------------------------------------------------------------------------
  const sim = {
    t: 0,
    y: initialState(),
    f: null,
    h: null,
    p: null,
    steps: 0,
    method: "dop853",
    dt: 0.001,
    error: null,
  };
  let history = [];
  let sectionPanel = null; // the Poincaré section panel (section.js), once built
  let energy0 = 0;
  let invariants0 = [];

  function advance(run, tEnd, options = {}) {
    const deadline = options.budget ? performance.now() + options.budget : Infinity;
    const rtol = options.rtol ?? RTOL;
    const atol = options.atol ?? ATOL;
    while (run.t < tEnd) {
      if ((run.method ?? "dop853") === "variational") {
        integrators.midpointStep(run, Math.min(run.dt, tEnd - run.t));
      } else {
        integrators.dopStep(run, tEnd, rtol, atol);
      }
      if (performance.now() > deadline) return false;
    }
    return true;
  }

  const observed = () => code.observables(sim.t, sim.y, params, inputs);

  function restart() {
    sim.t = 0;
    sim.y = initialState();
    sim.f = null;
    sim.h = null;
    sim.p = null;
    sim.steps = 0;
    sim.error = null;
    history = [];
    try {
      const [E, I] = observed();
      energy0 = flat(E)[0];
      invariants0 = flat(I);
    } catch (error) {
      fail(error);
    }
    try {
      measure();
    } catch (error) {
      fail(error);
    }
    record();
    fitView();
    layout();
    ui.hint.hidden = !atRest();
  }

  // whether the run starts at rest in an equilibrium (y' = 0): a model typed with no
  // initial state (m*x_dot**2/2 - k*x**2/2) stood still with no word of why
  function atRest() {
    try {
      return derivative(0, initialState()).every((x) => Math.abs(x) <= 1e-12);
    } catch (error) {
      return false;
    }
  }

  function record() {
    history.push({ t: sim.t, y: sim.y.slice(), point: trackedPoint() });
    if (history.length > MAX_HISTORY) history.splice(0, history.length - MAX_HISTORY);
  }

  // -- geometry --------------------------------------------------------------------------
  const D = scene.dimension;
  const origin = new Array(D).fill(0);

  function parts(t, y) {
    const [P, C, A, S, G, R] = code.scene(t, y, params, inputs);
    return { P, C, A: flat(A), S, G, R };
  }

  // sizes at the parameters now (as animate: dots of area ~ m^(2/3), bars of the uniform
  // rod's length sqrt(12 I / m), 3-D bodies as the box or disc of their mass and moments)
  let sizes = [];
  let lengths = [];
  let shapes = [];

  function measure() {
    const [, , , , , , m, W, J] = code.scene(0, initialState(), params, inputs);
    const masses = flat(m).map((x) => (Number.isFinite(x) && x > 0 ? x : 0));
    const heaviest = Math.max(0, ...masses);
    sizes = masses.map((x) => (heaviest > 0 ? (x / heaviest) ** (1 / 3) : 0.8));
    lengths = W.map(([mass, inertia]) => (mass > 0 && inertia > 0 ? Math.sqrt((12 * inertia) / mass) : 0));
    shapes = J.map(([mass, ...inertia]) => solidShape(mass, inertia));
  }

  // lagrangian.output.solids.solid_shape: the uniform box of the body's mass and principal
  // moments along its principal axes, half-sides a_k^2 = 3 (I_i + I_j - I_k) / (2 m); a flat
  // body with two equal moments is a disc of radius sqrt(2 I3 / m) with one spoke.  Points
  // in the body frame, joined by the paths (lists of point indices).
  function solidShape(mass, inertia) {
    const rules = scene.solid_rules;
    const point = { points: [[0, 0, 0]], paths: [] };
    const tensor = [0, 1, 2].map((i) => [0, 1, 2].map((j) => (inertia[3 * i + j] + inertia[3 * j + i]) / 2));
    const { values: moments, vectors: axes } = symmetricEigen(tensor);
    if (!(mass > 0) || !moments.every(Number.isFinite)) return point;
    const total = moments[0] + moments[1] + moments[2];
    const half = moments.map((I) => Math.sqrt(Math.max(0, (3 * (total - 2 * I)) / (2 * mass))));
    const largest = Math.max(...half);
    if (!(largest > 0)) return point;
    const thin = half.indexOf(Math.min(...half));
    const others = [0, 1, 2].filter((k) => k !== thin);
    const [a, b] = others.map((k) => moments[k]);
    if (half[thin] < rules.flat * largest && Math.abs(a - b) <= rules.equal * Math.max(a, b)) {
      const radius = Math.sqrt((2 * moments[thin]) / mass);
      const [u, v] = others.map((k) => axes[k]);
      const rim = [...Array(rules.rim_points).keys()].map((i) => {
        const angle = (2 * Math.PI * i) / rules.rim_points;
        return [0, 1, 2].map((j) => radius * (Math.cos(angle) * u[j] + Math.sin(angle) * v[j]));
      });
      const circle = [...rim.keys(), 0];
      return { points: [...rim, [0, 0, 0]], paths: [circle, [rim.length, 0]] };
    }
    // corner 4 i + 2 j + k has the signs (i, j, k) of the half-sides (0: minus, 1: plus);
    // each edge once, from the corner with the minus sign
    const corners = [...Array(8).keys()].map((c) => [4, 2, 1].map((bit) => (c & bit ? 1 : -1)));
    const points = corners.map((signs) => [0, 1, 2].map((j) => signs.reduce((sum, s, k) => sum + s * half[k] * axes[k][j], 0)));
    const paths = [];
    corners.forEach((signs, c) => [4, 2, 1].forEach((bit, k) => signs[k] < 0 && paths.push([c, c + bit])));
    return { points, paths };
  }

  // The eigenvalues (increasing) and unit eigenvectors of a symmetric 3 x 3 matrix, by
  // Jacobi's rotations (cyclic, to rounding).
  function symmetricEigen(matrix) {
    const A = matrix.map((row) => row.slice());
    const V = [[1, 0, 0], [0, 1, 0], [0, 0, 1]];
    for (let sweep = 0; sweep < 50; sweep++) {
      const off = Math.hypot(A[0][1], A[0][2], A[1][2]);
      const scale = Math.hypot(...A.flat());
      if (!(off > 1e-15 * scale)) break;
      for (const [p, q] of [[0, 1], [0, 2], [1, 2]]) {
        if (A[p][q] === 0) continue;
        const theta = (A[q][q] - A[p][p]) / (2 * A[p][q]);
        const t = Math.sign(theta || 1) / (Math.abs(theta) + Math.sqrt(theta * theta + 1));
        const c = 1 / Math.sqrt(t * t + 1);
        const s = t * c;
        for (let k = 0; k < 3; k++) {
          const [akp, akq] = [A[k][p], A[k][q]];
          A[k][p] = c * akp - s * akq;
          A[k][q] = s * akp + c * akq;
        }
        for (let k = 0; k < 3; k++) {
          const [apk, aqk] = [A[p][k], A[q][k]];
          A[p][k] = c * apk - s * aqk;
          A[q][k] = s * apk + c * aqk;
        }
        for (let k = 0; k < 3; k++) {
          const [vkp, vkq] = [V[k][p], V[k][q]];
          V[k][p] = c * vkp - s * vkq;
          V[k][q] = s * vkp + c * vkq;
        }
      }
    }
    const order = [0, 1, 2].sort((i, j) => A[i][i] - A[j][j]);
    return { values: order.map((i) => A[i][i]), vectors: order.map((i) => [0, 1, 2].map((k) => V[k][i])) };
  }

  function bodyEnds(p, k) {
    const half = lengths[k] / 2;
    const c = p.C[k];
    const a = p.A[k];
    return [
      [c[0] - half * Math.cos(a), c[1] - half * Math.sin(a)],
      [c[0] + half * Math.cos(a), c[1] + half * Math.sin(a)],
    ];
  }

  function solidOutline(p, k) {
    const R = p.R[k];
    const c = p.G[k];
    return shapes[k].points.map((b) => [0, 1, 2].map((i) => c[i] + R[3 * i] * b[0] + R[3 * i + 1] * b[1] + R[3 * i + 2] * b[2]));
  }

  function allPoints(p) {
    const points = [...p.P, ...p.S];
    p.C.forEach((_, k) => points.push(...bodyEnds(p, k).map((e) => [...e, ...new Array(D - 2).fill(0)])));
    p.G.forEach((_, k) => points.push(...solidOutline(p, k)));
    if (links.some((r) => r.includes(-1)) || stems.length) points.push(origin);
    return points;
  }

  function trackedPoint() {
    try {
      const p = parts(sim.t, sim.y);
      if (p.P.length) return p.P[p.P.length - 1];
      if (p.G.length) return p.G[p.G.length - 1];
      if (p.C.length) return [...p.C[p.C.length - 1], ...new Array(D - 2).fill(0)];
    } catch (error) {
      return null;
    }
    return null;
  }

  // Along a short, coarse run from the start: the box (D x [low, high]) of everything
  // drawn, and what `animate` decides along its run (lagrangian.output.geometry.rods): a rod
  // joins particle i to i - 1, else to the origin, where their distance stays constant; a
  // 3-D body whose centre stays at a constant distance from the origin turns about it; a
  // spring end that never moves is anchored.
  let extent = null;
  let links = [];
  let stems = [];
  let anchored = [];

  function fitView() {
    const probe = { t: 0, y: initialState(), f: null, h: null, p: null, steps: 0 };
    const horizon = Math.min(model.t_end, 10);
    const low = new Array(D).fill(Infinity);
    const high = new Array(D).fill(-Infinity);
    const samples = [];
    const include = (t, y) => {
      const p = parts(t, y);
      samples.push(p);
      for (const point of allPoints(p)) {
        point.forEach((x, i) => {
          if (Number.isFinite(x)) {
            low[i] = Math.min(low[i], x);
            high[i] = Math.max(high[i], x);
          }
        });
      }
    };
    try {
      include(probe.t, probe.y);
      const deadline = performance.now() + 150;
      for (let k = 1; k <= 100 && performance.now() < deadline; k++) {
        advance(probe, (horizon * k) / 100, { rtol: PROBE_RTOL, atol: PROBE_RTOL });
        include(probe.t, probe.y);
      }
    } catch (error) {
      // the page's own run will report it
    }
    extent = low.map((x, i) => (Number.isFinite(x) ? [x, high[i]] : [-1, 1]));
    const rigid = (first, second) => {
      const d = samples.map((p) => Math.hypot(...first(p).map((x, i) => x - second(p)[i])));
      const largest = Math.max(...d);
      return d.every(Number.isFinite) && largest > 0 && largest - Math.min(...d) <= scene.rod_tolerance * largest;
    };
    const point = (i) => (p) => (i < 0 ? origin : p.P[i]);
    links = [];
    if (!scene.coordinates_only && samples.length > 1) {
      scene.particles.forEach((_, i) => {
        const other = (i > 0 ? [i - 1, -1] : [-1]).find((j) => rigid(point(j), point(i)));
        if (other !== undefined) links.push([other, i]);
      });
    }
    stems = samples.length > 1 ? shapes.map((_, k) => k).filter((k) => rigid((p) => p.G[k], () => origin)) : [];
    anchored = [...Array(scene.springs)].map((_, s) =>
      [0, 1].map((e) => samples.every((p) => p.S[2 * s + e].every((x, i) => x === samples[0].S[2 * s + e][i]))),
    );
    holdTracks();
    // a hoop whole in view (a rail is longer than any view: clipped to it)
    for (const { points } of trackPoints(0, initialState()).filter((_, k) => heldTracks[k].closed)) {
      for (const point of points) point.forEach((x, i) => Number.isFinite(x) && (extent[i] = [Math.min(extent[i][0], x), Math.max(extent[i][1], x)]));
    }
    if (links.some((r) => r.includes(-1)) || stems.length) {
      extent = extent.map(([a, b]) => [Math.min(a, 0), Math.max(b, 0)]);
    }
  }

  // The curves particles are held to (page_content: geometry.tracks): a hoop or a rail is
  // drawn where it moves with t (a turning hoop, a turning wire: no pendulum's rod from
  // the origin then) or where no rod holds the particle (a bead on a fixed wire).  A closed
  // curve is drawn whole; an open one over q now -+ `half`, wide enough to cross the view.
  let heldTracks = [];

  function holdTracks() {
    const moving = new Set((scene.tracks || []).filter((t) => t.moving).map((t) => t.particle));
    links = links.filter(([a, b]) => !(a === -1 && moving.has(b)));
    // held by a rod: its far end (a cart at the near end of its pole still runs on a rail)
    const linked = new Set(links.map(([, b]) => b));
    const spans = extent.map(([low, high]) => high - low);
    const span = Math.max(...spans.filter(Number.isFinite), 1e-9);
    heldTracks = (scene.tracks || [])
      .filter((t) => t.moving || !linked.has(t.particle))
      .map((t) => {
        if (t.closed) return { ...t, half: Math.PI };
        // |dP/dq| at the start: an open curve crosses the view in about span / speed
        const y = initialState();
        const at = (q) => {
          const moved = y.slice();
          moved[t.coordinate] = q;
          return code.scene(0, moved, params, inputs)[0][t.particle];
        };
        const q0 = y[t.coordinate];
        const h = 1e-6 * Math.max(1, Math.abs(q0));
        const speed = Math.hypot(...at(q0 + h).map((x, i) => x - at(q0 - h)[i])) / (2 * h);
        return { ...t, half: speed > 0 ? (1.5 * span) / speed : 1 };
      });
  }

  // the points of each held track at time t, state y
  function trackPoints(t, y) {
    const SAMPLES = 96;
    return heldTracks.map((track) => {
      const centre = track.closed ? Math.PI : y[track.coordinate];
      const points = [];
      for (let k = 0; k <= SAMPLES; k++) {
        const moved = y.slice();
        moved[track.coordinate] = centre - track.half + (2 * track.half * k) / SAMPLES;
        points.push(code.scene(t, moved, params, inputs)[0][track.particle]);
      }
      return { particle: scene.particles[track.particle].name, points };
    });
  }

  function grow(p) {
    let grown = false;
    for (const point of allPoints(p)) {
      point.forEach((x, i) => {
        if (Number.isFinite(x) && (x < extent[i][0] || x > extent[i][1])) {
          extent[i] = [Math.min(extent[i][0], x), Math.max(extent[i][1], x)];
          grown = true;
        }
      });
    }
    return grown;
  }

  // (xlim, ylim) of every view: the extent plus a margin, one scale for all (as animate)
  function limits() {
    const spans = extent.map(([a, b]) => b - a);
    const largest = Math.max(...spans) > 0 ? Math.max(...spans) : 1;
    const margin = scene.style.margin * largest;
    const boxes = scene.views.map((axes) =>
      axes.map((axis) => {
        const [low, high] = extent[axis];
        const middle = (low + high) / 2;
        const half = Math.max((high - low) / 2 + margin, 0.2 * largest);
        return [middle - half, middle + half];
      }),
    );
    const tallest = Math.max(...boxes.map(([, y]) => y[1] - y[0]));
    return boxes.map(([x, y]) => [x, [(y[0] + y[1] - tallest) / 2, (y[0] + y[1] + tallest) / 2]]);
  }

  // -- drawing ---------------------------------------------------------------------------
  const ui = buildInterface();
  const canvas = ui.canvas;
  // opaque: the compositor copies the canvas instead of blending it over the page, every
  // frame (the 10-link chain: 4.3 -> 2.9 ms of the compositor's CPU per frame)
  const context = canvas.getContext("2d", { alpha: false });
  let panels = [];

  function layout() {
    const boxes = limits();
    const ratio = window.devicePixelRatio || 1;
    const width = Math.max(200, canvas.clientWidth);
    const gap = 16;
    const total = boxes.reduce((s, [x]) => s + (x[1] - x[0]), 0);
    const scale = (width - gap * (boxes.length - 1) - 8) / total;
    const height = Math.min(Math.max(...boxes.map(([, y]) => (y[1] - y[0]) * scale)) + 8, 0.7 * window.innerHeight);
    const fit = Math.min(scale, (height - 8) / Math.max(...boxes.map(([, y]) => y[1] - y[0])));
    canvas.width = Math.round(width * ratio);
    canvas.height = Math.round(height * ratio);
    canvas.style.height = `${height}px`;
    let left = 4;
    panels = boxes.map(([x, y], k) => {
      const panel = { axes: scene.views[k], x, y, left, top: 4, scale: fit, ratio };
      left += (x[1] - x[0]) * fit + gap;
      return panel;
    });
  }

  const screen = (panel, point) => [
    (panel.left + (point[panel.axes[0]] - panel.x[0]) * panel.scale) * panel.ratio,
    (panel.top + (panel.y[1] - point[panel.axes[1]]) * panel.scale) * panel.ratio,
  ];

  function line(points, color, width) {
    context.beginPath();
    points.forEach(([x, y], i) => (i ? context.lineTo(x, y) : context.moveTo(x, y)));
    context.strokeStyle = color;
    context.lineWidth = width;
    context.lineCap = "round";
    context.stroke();
  }

  function dot(x, y, radius, fill, stroke) {
    context.beginPath();
    context.arc(x, y, radius, 0, 2 * Math.PI);
    context.fillStyle = fill;
    context.fill();
    context.strokeStyle = stroke;
    context.lineWidth = 1;
    context.stroke();
  }

  // a spring from a to b (screen points) as a zigzag: straight leads on 15 % at each end
  function zigzag(a, b, width, coils = 8) {
    const along = [b[0] - a[0], b[1] - a[1]];
    const length = Math.hypot(...along);
    if (length === 0) return [a, b];
    const normal = [-along[1] / length, along[0] / length];
    const points = [a, [a[0] + 0.15 * along[0], a[1] + 0.15 * along[1]]];
    for (let k = 1; k < 2 * coils; k++) {
      const s = 0.15 + (0.7 * k) / (2 * coils);
      const side = k % 2 ? width : -width;
      points.push([a[0] + s * along[0] + side * normal[0], a[1] + s * along[1] + side * normal[1]]);
    }
    points.push([a[0] + 0.85 * along[0], a[1] + 0.85 * along[1]], b);
    return points;
  }

  const radius = (k, ratio) => (4 + 6 * sizes[k]) * ratio;

  function draw() {
    let p;
    try {
      p = parts(sim.t, sim.y);
    } catch (error) {
      fail(error);
      return;
    }
    if (grow(p)) layout();
    const style = scene.style;
    context.setTransform(1, 0, 0, 1, 0, 0);
    context.fillStyle = "#ffffff"; // the canvas' background (page.css), painted: it is opaque
    context.fillRect(0, 0, canvas.width, canvas.height);
    const trailStart = sim.t - 1;
    for (const panel of panels) {
      const r = panel.ratio;
      const at = (point) => screen(panel, point);
      context.strokeStyle = "#e4e7eb";
      context.lineWidth = 1 * r;
      const [x0, y0] = at(panel.axes.reduce((o, a, i) => ((o[a] = i ? panel.y[0] : panel.x[0]), o), origin.slice()));
      const [x1, y1] = at(panel.axes.reduce((o, a, i) => ((o[a] = i ? panel.y[1] : panel.x[1]), o), origin.slice()));
      context.strokeRect(x0, y1, x1 - x0, y0 - y1);
      if (scene.views.length > 1) {
        context.fillStyle = "#5b6570";
        context.font = `${11 * r}px sans-serif`;
        const axisNames = ["x", "y", "z"];
        const kind = panel.axes[1] === scene.vertical ? "side view" : "top view";
        context.fillText(`${kind} (${axisNames[panel.axes[0]]}-${axisNames[panel.axes[1]]})`, x0 + 6 * r, y1 + 14 * r);
      }
      // the trail of the last particle
      const trail = history.filter((s) => s.t >= trailStart && s.point);
      for (let k = 1; k < trail.length; k++) {
        const alpha = style.trail_alpha * (k / trail.length);
        line([at(trail[k - 1].point), at(trail[k].point)], hexAlpha(scene.particles.length ? scene.particles[scene.particles.length - 1].color : style.body, alpha), 1.8 * r);
      }
      if (heldTracks.length) {
        // the hoops and rails, thin, within the panel (a rail is longer than the view)
        context.save();
        context.beginPath();
        context.rect(x0, y1, x1 - x0, y0 - y1);
        context.clip();
        for (const { points } of trackPoints(sim.t, sim.y)) line(points.map(at), style.track, 1.4 * r);
        context.restore();
      }
      p.S.forEach((_, s) => {
        const a = at(p.S[2 * s] ?? origin);
        const b = at(p.S[2 * s + 1] ?? origin);
        if (s < scene.springs) line(zigzag(a, b, 6 * r), style.spring, 1.2 * r);
      });
      for (let s = 0; s < scene.springs; s++) {
        (anchored[s] || []).forEach((fixed, e) => {
          if (fixed) {
            const [x, y] = at(p.S[2 * s + e]);
            context.fillStyle = style.pivot;
            context.fillRect(x - 4 * r, y - 4 * r, 8 * r, 8 * r);
          }
        });
      }
      for (const [a, b] of links) {
        line([at(a < 0 ? origin : p.P[a]), at(b < 0 ? origin : p.P[b])], style.rod, 2.2 * r);
      }
      for (const k of stems) line([at(origin), at(p.G[k])], style.rod, 2.2 * r);
      p.C.forEach((c, k) => {
        const ends = bodyEnds(p, k).map((e) => [...e, ...new Array(D - 2).fill(0)]);
        context.globalAlpha = 0.85;
        line(ends.map(at), style.body, 7 * r);
        context.globalAlpha = 1;
        const [x, y] = at([...c, ...new Array(D - 2).fill(0)]);
        dot(x, y, 3 * r, "#ffffff", "#000000");
      });
      p.G.forEach((c, k) => {
        const outline = solidOutline(p, k).map(at);
        for (const path of shapes[k].paths) line(path.map((i) => outline[i]), style.solid, 1.6 * r);
        const [x, y] = at(c);
        dot(x, y, 3 * r, "#ffffff", "#000000");
      });
      if (links.some((rod) => rod.includes(-1)) || stems.length) {
        const [x, y] = at(origin);
        dot(x, y, 4 * r, "#ffffff", style.pivot);
      }
      p.P.forEach((point, k) => {
        const [x, y] = at(point);
        dot(x, y, radius(k, r), scene.particles[k].color, "#333333");
      });
    }
    context.fillStyle = "#1d232b";
    context.font = `${12 * (window.devicePixelRatio || 1)}px ui-monospace, monospace`;
    const ratio = window.devicePixelRatio || 1;
    context.fillText(`t = ${sim.t.toFixed(2)}`, 10 * ratio, canvas.height - 10 * ratio);
  }

  function hexAlpha(color, alpha) {
    const value = parseInt(color.slice(1), 16);
    return `rgba(${(value >> 16) & 255}, ${(value >> 8) & 255}, ${value & 255}, ${alpha.toFixed(3)})`;
  }

  // -- the plots beside the mechanism ----------------------------------------------------
  function drawPlots() {
    const k = Number(ui.phaseChoice.value) || 0;
    const window20 = history.filter((s) => s.t >= sim.t - 20);
    const every = Math.ceil(window20.length / PLOT_POINTS);
    const recent = window20.filter((_, i) => i % every === 0 || i === window20.length - 1);
    const shown = (name) => model.symbols[name] ?? name; // theta1_dot as θ̇₁
    // A dimensioned model's axes say their SI units: "θ₁ [rad]", "t [s]"; else the name.
    const inUnit = (label, unit) => (unit ? `${label} [${unit}]` : label);
    const unitOf = (name) => (model.units ? model.units[name] : undefined);
    const axis = (name) => inUnit(shown(name), unitOf(name));
    // several coordinates on one axis "q": a unit only where they all have the same one
    const shared = names.every((q) => unitOf(q) === unitOf(names[0])) ? unitOf(names[0]) : undefined;
    lagrangianPlot(ui.phase, [{ color: "#1f77b4", points: recent.map((s) => [s.y[k], s.y[n + k]]) }], [axis(names[k]), axis(rates[k])]);
    lagrangianPlot(
      ui.series,
      names.map((q, i) => ({ label: shown(q), color: scene.palette[i % scene.palette.length], points: recent.map((s) => [s.t, s.y[i]]) })),
      [axis("t"), names.length === 1 ? axis(names[0]) : inUnit("q", shared)],
    );
  }

  // -- readouts ----------------------------------------------------------------------------
  // A quantity that starts at 0 (a momentum from rest) drifts by its change itself:
  // divided by a start of 0 (or 1e-300 in its place) it read -4.72e+284.
  const STARTS_AT_ZERO = 1e-12;
  const relative = (value, start) => ((value - start) / Math.abs(start)).toExponential(2);
  const absolute = (value, start) => (value - start).toExponential(2);

  // A dimensioned model's unit after a readout (its values are SI): " s", " J"; else "".
  const unit = (name) => (model.units && model.units[name] ? ` ${model.units[name]}` : "");

  function readouts() {
    let E;
    let I;
    try {
      [E, I] = observed();
    } catch (error) {
      fail(error);
      return;
    }
    const energy = flat(E)[0];
    const lines = [
      `t = ${sim.t.toFixed(3)}${unit("t")}`,
      `energy h = ${energy.toPrecision(10)}${unit("energy")}`,
      Math.abs(energy0) > STARTS_AT_ZERO ? `drift (h - h0)/|h0| = ${relative(energy, energy0)}` : `drift h - h0 = ${absolute(energy, energy0)}`,
      `steps: ${sim.steps} (${sim.t > 0 ? (sim.steps / sim.t).toFixed(0) : 0} per s)`,
      `frames per second: ${fps.toFixed(0)}`,
    ];
    flat(I).forEach((value, k) => {
      const quantity = model.conserved[k];
      if (quantity.name === "energy") return;
      const start = invariants0[k];
      const change = Math.abs(start) > STARTS_AT_ZERO ? `drift ${relative(value, start)}` : `absolute drift ${absolute(value, start)}`;
      lines.push(`${quantity.name} = ${value.toPrecision(10)}${unit(quantity.name)} (${change})`);
    });
    if (sim.error) lines.push(`stopped: ${sim.error}`);
    const rows = ui.readouts.children;
    if (rows.length !== lines.length) {
      ui.readouts.replaceChildren(...lines.map((text) => element("div", {}, text)));
    } else {
      lines.forEach((text, k) => {
        if (rows[k].textContent !== text) rows[k].textContent = text;
      });
    }
  }

  function fail(error) {
    sim.error = String(error && error.message ? error.message : error);
    running = false;
    ui.play.textContent = "Play";
    ui.status.textContent = `The integration stopped: ${sim.error}`;
  }

  // -- the loop ----------------------------------------------------------------------------
  let running = true;
  let speed = 1;
  let last = null;
  let fps = 0;
  let frames = 0;
  let frameClock = performance.now();
  let shown = -Infinity; // when the plots and readouts were last redrawn
  let work = 0; // ms spent in the frames of the current second
  let frameWork = 0; // ms per frame over the last second: integration, drawing, plots

  function frame(now) {
    const started = performance.now();
    if (running && last !== null && !sim.error) {
      const wall = Math.min(0.1, (now - last) / 1000);
      try {
        advance(sim, sim.t + speed * wall, { budget: WORK_BUDGET_MS });
        record();
      } catch (error) {
        fail(error);
      }
    }
    last = now;
    frames += 1;
    draw();
    if (now - shown >= PANEL_MS || !running) {
      // the plots and readouts at a few updates per second: redrawn every frame, their
      // rasterisation took more time than the mechanism's (the 10-link chain: 23 -> 58 fps)
      shown = now;
      drawPlots();
      readouts();
    }
    work += performance.now() - started;
    if (now - frameClock >= 1000) {
      fps = (1000 * frames) / (now - frameClock);
      frameWork = work / frames;
      frames = 0;
      work = 0;
      frameClock = now;
    }
    window.requestAnimationFrame(frame);
  }

  // -- dragging a particle -----------------------------------------------------------------
  let dragging = null;

  function pointer(event) {
    const box = canvas.getBoundingClientRect();
    const ratio = window.devicePixelRatio || 1;
    return [(event.clientX - box.left) * ratio, (event.clientY - box.top) * ratio];
  }

  canvas.addEventListener("pointerdown", (event) => {
    const [x, y] = pointer(event);
    const p = parts(sim.t, sim.y);
    let best = null;
    panels.forEach((panel) => {
      p.P.forEach((point, k) => {
        const [u, v] = screen(panel, point);
        const distance = Math.hypot(u - x, v - y);
        if (distance <= radius(k, panel.ratio) + 6 * panel.ratio && (!best || distance < best.distance)) {
          best = { k, panel, distance };
        }
      });
    });
    if (!best) return;
    dragging = { ...best, wasRunning: running };
    running = false;
    canvas.setPointerCapture(event.pointerId);
  });

  canvas.addEventListener("pointermove", (event) => {
    if (!dragging) return;
    const [x, y] = pointer(event);
    const panel = dragging.panel;
    const target = [panel.x[0] + (x / panel.ratio - panel.left) / panel.scale, panel.y[1] - (y / panel.ratio - panel.top) / panel.scale];
    const q = placed(dragging.k, panel.axes, target);
    if (q) {
      names.forEach((name, i) => (initial[name] = q[i]));
      rates.forEach((name) => (initial[name] = 0));
      sim.t = 0;
      sim.y = initialState();
      history = [];
      record();
      showValues();
      draw();
    }
  });

  const release = () => {
    if (!dragging) return;
    const resume = dragging.wasRunning;
    dragging = null;
    restart();
    setRunning(resume);
  };
  canvas.addEventListener("pointerup", release);
  canvas.addEventListener("pointercancel", release);

  // q that brings particle k nearest to `target` in the view's axes, least squares from
  // the current q by Gauss-Newton (a small pull towards the current q keeps it unique)
  function placed(k, axes, target) {
    let q = sim.y.slice(0, n);
    const start = q.slice();
    const zeros = new Array(n).fill(0);
    const residual = (x) => {
      const point = code.scene(0, [...x, ...zeros], params, inputs)[0][k];
      return axes.map((a, i) => point[a] - target[i]);
    };
    const weight = 1e-3;
    for (let iteration = 0; iteration < 30; iteration++) {
      const r = residual(q);
      const J = q.map((_, j) => {
        const e = 1e-7 * Math.max(1, Math.abs(q[j]));
        const shifted = q.slice();
        shifted[j] += e;
        return residual(shifted).map((v, i) => (v - r[i]) / e);
      });
      const normal = q.map((_, a) => q.map((__, b) => J[a].reduce((s, v, i) => s + v * J[b][i], 0) + (a === b ? weight : 0)));
      const gradient = q.map((_, a) => -(J[a].reduce((s, v, i) => s + v * r[i], 0) + weight * (q[a] - start[a])));
      let step;
      try {
        step = code.solve(normal, gradient);
      } catch (error) {
        return null;
      }
      q = q.map((v, i) => v + step[i]);
      if (Math.max(...step.map(Math.abs)) < 1e-10) break;
    }
    return q.every(Number.isFinite) ? q : null;
  }

  // -- the controls ------------------------------------------------------------------------
  function element(tag, attributes = {}, text = null) {
    const node = document.createElement(tag);
    for (const [key, value] of Object.entries(attributes)) node.setAttribute(key, value);
    if (text !== null) node.textContent = text;
    return node;
  }

  function buildInterface() {
    document.title = model.name;
    document.getElementById("title").textContent = model.name;
    document.getElementById("description").textContent = model.description;
    const live = document.getElementById("live");
    const mechanism = element("canvas", { class: "mechanism", "aria-label": "the mechanism in motion" });
    const play = element("button", { type: "button" }, "Pause");
    const reset = element("button", { type: "button" }, "Reset");
    const speedChoice = element("select", { "aria-label": "speed" });
    for (const value of [0.1, 0.25, 0.5, 1, 2, 4]) {
      const option = element("option", { value: String(value) }, `${value}x`);
      if (value === 1) option.selected = true;
      speedChoice.append(option);
    }
    const methodChoice = element("select", { "aria-label": "integrator" });
    methodChoice.append(element("option", { value: "dop853" }, "adaptive DOP853 (rtol 1e-12)"));
    if (variationalAvailable) methodChoice.append(element("option", { value: "variational" }, "variational midpoint (dt 0.001)"));
    const status = element("div", { class: "error", role: "status" });
    const buttons = element("div", { class: "buttons" });
    const shareButton = element("button", { type: "button", title: "a link to this run: its values, integrator and time" }, "Share link");
    const embedButton = element("button", { type: "button", title: "HTML for a course page or slides" }, "Embed");
    buttons.append(play, reset, element("span", {}, "speed"), speedChoice, methodChoice, shareButton, embedButton);
    const first = names[0];
    const hint = element(
      "p",
      { class: "hint", role: "note", hidden: "" },
      `At rest in an equilibrium, so nothing moves: drag a mass, or give an initial value (${first} or ${rates[0]} below), to start the motion.`,
    );
    const shared = element("input", { type: "text", readonly: "", class: "shared", "aria-label": "link to share", hidden: "" });
    const readoutBox = element("div", { class: "readouts" });
    const phase = element("canvas", { "aria-label": "phase portrait" });
    const series = element("canvas", { "aria-label": "time series" });
    const phaseChoice = element("select", { "aria-label": "coordinate of the phase portrait" });
    names.forEach((name, i) => phaseChoice.append(element("option", { value: String(i) }, model.symbols[name] ?? name)));
    const phaseFigure = element("figure");
    const phaseCaption = element("figcaption", {}, "phase portrait of ");
    phaseCaption.append(phaseChoice);
    phaseFigure.append(phase, phaseCaption);
    const seriesFigure = element("figure");
    seriesFigure.append(series, element("figcaption", {}, "coordinates against time (last 20 s)"));
    const plots = element("div", { class: "plots" });
    plots.append(phaseFigure, seriesFigure);
    const fields = {};
    const parameterBox = element("fieldset");
    parameterBox.append(element("legend", {}, "Parameters"));
    model.parameters.forEach((p) => parameterBox.append(field(p.name, p.value, fields, true)));
    const boxes = [parameterBox];
    if (model.inputs.length) {
      const inputBox = element("fieldset");
      inputBox.append(element("legend", {}, "Inputs (held constant)"));
      model.inputs.forEach((u) => inputBox.append(field(u.name, u.value, fields, false)));
      boxes.push(inputBox);
    }
    const initialBox = element("fieldset");
    initialBox.append(element("legend", {}, "Initial state (drag a mass to place it)"));
    names.forEach((q, i) => {
      initialBox.append(field(q, initial[q], fields, false));
      initialBox.append(field(rates[i], initial[rates[i]], fields, false));
    });
    live.append(mechanism, buttons, hint, shared, status, readoutBox, plots, ...boxes, initialBox);
    const offer = (text) => {
      shared.hidden = false;
      shared.value = text;
      shared.select();
      // the field, selected, stays for Ctrl+C; the clipboard is tried only at the top (in a
      // sandboxed frame its mere use is a console error: a permissions policy violation)
      if (window.self === window.top && navigator.clipboard) navigator.clipboard.writeText(text).catch(() => {});
    };
    shareButton.addEventListener("click", () => offer(shareLink()));
    embedButton.addEventListener("click", () => {
      const address = shareLink().replace("#", "#embed&");
      offer(`<iframe sandbox="allow-scripts" src="${address.replace(/&/g, "&amp;").replace(/"/g, "&quot;")}" width="640" height="560" title="${model.name.replace(/[<>&"]/g, "")}"></iframe>`);
    });
    play.addEventListener("click", () => setRunning(!running));
    reset.addEventListener("click", () => restart());
    speedChoice.addEventListener("change", () => (speed = Number(speedChoice.value)));
    methodChoice.addEventListener("change", () => {
      sim.method = methodChoice.value;
      restart();
    });
    phaseChoice.addEventListener("change", () => drawPlots());
    return { canvas: mechanism, hint, play, status, readouts: readoutBox, phase, series, phaseChoice, fields, methodChoice };
  }

  function field(name, value, fields, isParameter) {
    const row = element("div", { class: "field" });
    const label = element("label", { title: name });
    if (window.katex && model.labels[name]) {
      window.katex.render(model.labels[name], label, { throwOnError: false, strict: "ignore" });
    } else {
      label.textContent = name;
    }
    const magnitude = Math.abs(value);
    const [low, high] = isParameter && value > 0 ? [0, 3 * value] : [value - Math.max(3, 2 * magnitude), value + Math.max(3, 2 * magnitude)];
    const step = sliderStep(value);
    const slider = element("input", { type: "range", min: String(low), max: String(high), step: String(step), value: String(value), "aria-label": name });
    const number = element("input", { type: "number", step: "any", value: String(value), "aria-label": `${name} value` });
    const apply = (text) => {
      const x = Number(text);
      if (!Number.isFinite(x)) return;
      try {
        set(name, x);
        ui.status.textContent = "";
      } catch (error) {
        // refused (a mass of -1): said as the command line says it, the value kept
        ui.status.textContent = error.message;
        showValues();
      }
    };
    slider.addEventListener("input", () => apply(slider.value));
    number.addEventListener("change", () => apply(number.value));
    row.append(label, slider, number);
    fields[name] = { slider, number };
    return row;
  }

  // A step the slider's own value lies on (9.81 -> 0.01, 0.3 -> 0.001, 1.2345 -> 0.0001):
  // a hundredth of its magnitude, finer where the value has more digits; the ends of the
  // range (0, 3 value; value -+ max(3, 2 |value|)) lie on it too.  A step of a thousandth
  // of the range put 9.81 between two grid points, and the slider never came back to it.
  function sliderStep(value) {
    if (!(Math.abs(value) > 0)) return 0.01;
    let step = 10 ** (Math.floor(Math.log10(Math.abs(value))) - 2);
    const off = (x) => Math.abs(x / step - Math.round(x / step)) > 1e-9 * Math.abs(x / step);
    for (let finer = 0; finer < 10 && off(value); finer++) step /= 10;
    return Number(step.toPrecision(1));
  }

  function showValues() {
    const values = { ...initial };
    parameterNames.forEach((name, i) => (values[name] = params[i]));
    inputNames.forEach((name, i) => (values[name] = inputs[i]));
    for (const [name, { slider, number }] of Object.entries(ui.fields)) {
      const value = values[name];
      if (document.activeElement !== number) number.value = String(Number(value.toPrecision(12)));
      if (document.activeElement !== slider) {
        if (value < Number(slider.min)) slider.min = String(value);
        if (value > Number(slider.max)) slider.max = String(value);
        slider.value = String(value);
      }
    }
  }

  function setRunning(value) {
    running = value;
    ui.play.textContent = running ? "Pause" : "Play";
  }

  // -- the worked solution -------------------------------------------------------------------
  function typeset() {
    const solution = document.getElementById("solution");
    for (const section of model.sections) {
      const box = section.folded ? element("details") : element("div");
      box.append(section.folded ? element("summary", {}, section.title) : element("h2", {}, section.title));
      // a folded section is typeset when first opened (a linkage's steps: rows of 28k characters)
      const fill = () => { for (const item of section.items) box.append(itemNode(item)); };
      if (section.folded) whenOpened(box, fill);
      else fill();
      solution.append(box);
    }
  }

  function itemNode(item) {
    if (item.folded !== undefined) return foldedRow(item);
    const node = element("div", { class: "item" });
    if (item.equilibrium) {
      node.append(results.block(item.equilibrium));
    } else if (item.latex && item.wrap) {
      const math = element("div", { class: "math wrap" });
      typesetMath(item.latex, math, false);
      node.append(math);
    } else if (item.latex) {
      const math = element("div", { class: "math" });
      typesetMath(item.latex, math, true);
      node.append(math);
    }
    if (item.text) node.append(element("p", {}, item.text));
    return node;
  }

  // a row too long to typeset at load (page_folding.py): its left side in a closed
  // <details>, the whole row typeset when it is first opened
  function foldedRow(item) {
    const box = element("details", { class: "item folded-row" });
    const summary = element("summary");
    const name = element("span");
    typesetMath(item.folded, name, false);
    summary.append(name, ` in full (${item.latex.length.toLocaleString("en")} characters of LaTeX)`);
    box.append(summary);
    whenOpened(box, () => {
      const math = element("div", { class: "math" });
      typesetMath(item.latex, math, true);
      box.append(math);
    });
    return box;
  }

  function whenOpened(details, fill) {
    const opened = () => {
      if (!details.open) return;
      details.removeEventListener("toggle", opened);
      fill();
    };
    details.addEventListener("toggle", opened);
  }

  // display math (or inline, which KaTeX breaks after a top-level + or =) into `node`
  function typesetMath(latex, node, display) {
    if (window.katex) {
      window.katex.render(latex, node, { displayMode: display, throwOnError: false, strict: "ignore", trust: false });
    } else {
      node.textContent = latex;
    }
  }

  // -- the share link (share.js) ----------------------------------------------------------------
  const sharing = lagrangianShare();

  // the run as the link has it: paused, and stepped from t = 0 to now in one call, as the
  // page that opens the link steps it (frame by frame, the steps end at other times)
  function shareLink() {
    setRunning(false);
    const t = sim.t;
    restart();
    advance(sim, t);
    record();
    const run = {
      parameters: Object.fromEntries([...parameterNames.map((name, i) => [name, params[i]]), ...inputNames.map((name, i) => [name, inputs[i]])]),
      initial: Object.fromEntries([...names, ...rates].map((name) => [name, initial[name]])),
      method: sim.method,
      t: sim.t,
    };
    return sharing.link(run);
  }

  // the values, integrator and time of the link the page was opened with; what does not
  // fit the model is said in the status line and left out
  function openLink(hash) {
    const asked = sharing.read(hash);
    const problems = [...asked.problems];
    for (const [name, value] of Object.entries(asked.parameters)) {
      if (refused(name, value)) problems.push(refused(name, value));
      else if (parameterNames.includes(name)) params[parameterNames.indexOf(name)] = value;
      else if (inputNames.includes(name)) inputs[inputNames.indexOf(name)] = value;
      else problems.push(`'${name}' is not a parameter of this model`);
    }
    for (const [name, value] of Object.entries(asked.initial)) {
      if (name in initial) initial[name] = value;
      else problems.push(`'${name}' is not a coordinate or velocity of this model`);
    }
    if (asked.method !== null) {
      const known = [...ui.methodChoice.options].map((o) => o.value);
      if (known.includes(asked.method)) {
        sim.method = asked.method;
        ui.methodChoice.value = asked.method;
      } else {
        problems.push(`'${asked.method}' is not an integrator of this page (${known.join(", ")})`);
      }
    }
    if (asked.t !== null && asked.t < 0) problems.push(`t: must be 0 or later, not ${asked.t}`);
    if (problems.length) ui.status.textContent = `The link: ${problems.join("; ")} (left out).`;
    if (asked.embed) document.body.classList.add("embed");
    return asked.t !== null && asked.t > 0 ? asked.t : 0;
  }

  // -- the hook -------------------------------------------------------------------------------
  // lagrangian.model.values.check_parameter_value: the same rule and words as --set
  const SIGN_BREAKS = { positive: (x) => x <= 0, nonnegative: (x) => x < 0, negative: (x) => x >= 0 };
  const SIGN_RANGE = { positive: "> 0", nonnegative: ">= 0", negative: "< 0" };

  function refused(name, x) {
    const parameter = model.parameters.find((p) => p.name === name);
    const breaks = parameter && SIGN_BREAKS[parameter.sign];
    if (!breaks || !breaks(x)) return parameter ? bodyRefused(name, x) : null;
    const sign = parameter.sign;
    return (
      `parameter ${name} = ${pythonG(x)} breaks the model's assumption that ${name} is ${sign} (the equations were derived with it): ` +
      `give a value ${SIGN_RANGE[sign]}, or declare ${name} = {value = ..., sign = "real"} in the model`
    );
  }

  // lagrangian.model.values.check_parameter_values' checks of the bodies at the value x of
  // `name`, in its order: each 3-D body's inertia (inertia.js), then each mass (and planar
  // moment of inertia) that uses it; the values from the scene routine at the parameters x
  // would make
  function bodyRefused(name, x) {
    const inertias = (model.inertias || []).filter((entry) => entry.used.includes(name));
    const entries = (model.masses || []).filter((entry) => entry.used.includes(name));
    if (!inertias.length && !entries.length) return null;
    const trial = params.slice();
    trial[parameterNames.indexOf(name)] = x;
    let blocks;
    try {
      const [, , , , , , m, W, J] = code.scene(0, initialState(), trial, inputs);
      blocks = { m, W, J };
    } catch (error) {
      return null;
    }
    for (const entry of inertias) {
      const problem = inertiaProblem(entry, blocks.J[entry.row], pythonG);
      if (problem) return `${entry.field}: ${problem} (with ${name} = ${pythonG(x)})`;
    }
    for (const entry of entries) {
      const [block, row, column] = entry.at;
      const value = blocks[block][row][column];
      if (SIGN_BREAKS[entry.sign](value)) {
        return `${entry.what} is ${pythonG(value)} with ${name} = ${pythonG(x)}: it must be ${SIGN_RANGE[entry.sign]}`;
      }
    }
    return null;
  }

  // Python's format(x, "g"): 6 significant digits, no trailing zeros, an exponent of two
  // digits or more below 1e-4 and from 1e6
  function pythonG(x) {
    if (x === 0) return "0";
    const [mantissa, power] = x.toExponential(5).split("e");
    const exponent = Number(power);
    if (exponent < -4 || exponent >= 6) {
      const digits = String(Math.abs(exponent)).padStart(2, "0");
      return `${mantissa.replace(/\.?0+$/, "")}e${exponent < 0 ? "-" : "+"}${digits}`;
    }
    return String(Number(x.toPrecision(6)));
  }

  function set(name, value) {
    const x = Number(value);
    if (!Number.isFinite(x)) throw new Error(`${name}: not a finite number: ${value}`);
    const refusal = refused(name, x);
    if (refusal) throw new Error(refusal);
    const index = parameterNames.indexOf(name);
    if (index >= 0) params[index] = x;
    else if (inputNames.includes(name)) inputs[inputNames.indexOf(name)] = x;
    else if (name in initial) initial[name] = x;
    else throw new Error(`'${name}' is neither a parameter nor a coordinate or velocity`);
    restart();
    showValues();
    results.update(params);
    if (sectionPanel) sectionPanel.clear(); // its orbits were of the values before
  }

  function state() {
    return {
      t: sim.t,
      q: Object.fromEntries(names.map((q, i) => [q, sim.y[i]])),
      q_dot: Object.fromEntries(rates.map((v, i) => [names[i], sim.y[n + i]])),
    };
  }

  sectionPanel = lagrangianSection(model, {
    derivative,
    energy: (t, y) => flat(code.observables(t, y, params, inputs)[0])[0],
    momenta: (t, y) => flat(code.variational(t, y, params, inputs)[0]),
    massMatrix: (t, y) => code.mass_matrix(t, y, params, inputs),
    solve: code.solve,
    now: () => ({ t: sim.t, y: sim.y.slice() }),
    start: initialState,
  }, element);
  document.getElementById("live").append(sectionPanel.panel);

  window.lagrangian = Object.freeze({
    get parameters() {
      return Object.fromEntries(parameterNames.map((name, i) => [name, params[i]]));
    },
    get inputs() {
      return Object.fromEntries(inputNames.map((name, i) => [name, inputs[i]]));
    },
    state,
    set,
    run(tEnd) {
      const target = Number(tEnd);
      if (!Number.isFinite(target)) throw new Error(`run: not a finite time: ${tEnd}`);
      if (target < sim.t) restart();
      advance(sim, target);
      record();
      return state();
    },
    energy: () => flat(observed()[0])[0],
    conserved: () => Object.fromEntries(flat(observed()[1]).map((v, k) => [model.conserved[k].name, v])),
    results: results.now,
    tracks: () => trackPoints(sim.t, sim.y),
    rods: () => links.map((link) => link.map((i) => (i < 0 ? "origin" : scene.particles[i].name))),
    link: shareLink,
    section: sectionPanel.hook, // the Poincaré section panel (section.js)
    embedded: () => document.body.classList.contains("embed"),
    reset: restart,
    play: () => setRunning(true),
    pause: () => setRunning(false),
    stats: () => ({ fps, frame_ms: frameWork, steps: sim.steps, steps_per_second: sim.t > 0 ? sim.steps / sim.t : 0, method: sim.method }),
    solids() {
      const p = parts(sim.t, sim.y);
      return p.G.map((center, k) => ({ center, outline: solidOutline(p, k) }));
    },
    screenPosition(particle) {
      const k = scene.particles.findIndex((p) => p.name === particle);
      if (k < 0 || !panels.length) return null;
      const [x, y] = screen(panels[0], parts(sim.t, sim.y).P[k]);
      return [x / panels[0].ratio, y / panels[0].ratio];
    },
  });

  const linkedTime = openLink(window.location.hash);
  showValues();
  typeset();
  results.update(params);
  const solution = document.getElementById("solution");
  results.fit(solution);
  // again once KaTeX's fonts are in: measured with the fallback fonts, formulas are narrower
  if (document.fonts) document.fonts.ready.then(() => results.fit(solution));
  restart();
  sectionPanel.draw(); // the empty plane about the state now, ready for a click
  if (linkedTime > 0) {
    // the moment of the link, paused there
    advance(sim, linkedTime);
    record();
    setRunning(false);
  }
  window.addEventListener("resize", () => {
    layout();
    sectionPanel.draw();
    results.fit(solution);
  });
  window.requestAnimationFrame(frame);
}
