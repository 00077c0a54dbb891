// The Poincaré section panel (lagrangian page): the crossings of a section q_c = value in
// a plane (q_a, q_a' or p_a), and a click in the plane that starts an orbit there on the
// energy shell.
//
// Each orbit is integrated by the page's DOP853 (integrators.js, SciPy's step control) at
// lagrangian poincare's tolerances (rtol 1e-10, atol 1e-12) and its crossings are the
// roots of g = q_c - value on the step's 7th-order dense output (SciPy's Dop853DenseOutput:
// 3 more stages and the coefficients D, given by lagrangian.output.page_section), found by
// bisection to 4 ulp of t, where the sign of g at the step's ends changes in the section's
// direction: the points of `lagrangian poincare MODEL --section "q_c = value"` from the same
// start.  A start on the section is not a crossing (lagrangian.integrate.events).  An orbit
// is integrated in slices of a few milliseconds with the page free between them (a long
// orbit would freeze it): its points appear as they come, and the status line says how far
// it got.
//
// A click at (u, w) starts an orbit with q_a = u, q_c = value, the other coordinates and
// velocities at their values in the run now (the state of the moment), and
//   * axes (q_a, q_a'): q_a' = w, and q_c' from h(q, q') = E;
//   * axes (q_a, p_a): q_a' and q_c' together from p_a = w and h = E.  For a Lagrangian
//     quadratic in the velocities p = M q' + b is affine in q': at each trial q_c', q_a' is
//     the exact solution of p_a(q_a') = w, q_a' = q_a'0 + (w - p_a(q_a'0)) / M_aa.  Along
//     that line h is a quadratic in q_c' alone (a quadratic of an affine map).
// The quadratic's coefficients are read from h at q_c' = -1, 0, 1 and checked at q_c' = 2
// (a model not quadratic in the velocities, or not convex, is refused); the root is the
// larger for the direction "+", the smaller for "-", and must cross in that direction
// (q_c' > 0 for "+").  No real root: the point is outside the energy-allowed region, and
// the status line says so.  E is the energy of the run now, or the number typed.
//
// system: derivative(t, y), energy(t, y), momenta(t, y) -> p, massMatrix(t, y), solve,
// now() -> {t, y} the run's state of the moment, start() -> the run's initial state.
function lagrangianSection(model, system, element) {
  "use strict";
  const RTOL = 1e-10;
  const ATOL = 1e-12;
  const MAX_STEPS = 200000;
  const COLORS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22"];
  const n = model.coordinates.length;
  const names = model.coordinates.map((c) => c.name);
  const shown = (name) => model.symbols[name] ?? name;
  const panel = element("fieldset", { class: "poincare" });
  panel.append(element("legend", {}, "Poincaré section"));
  if (!model.section || !model.section.available) {
    panel.append(element("p", { class: "hint" }, model.section ? model.section.why : "No Poincaré section for this model."));
    return { panel, hook: null, clear() {}, draw() {} };
  }
  const dense = model.section.dense;
  const SLICE_MS = 12; // of integration between two chances for the page to draw and respond
  const orbits = [];
  const running = new Set(); // the promises of the orbits being integrated (settled(), see track)
  let clears = 0; // how many times the plane was cleared: an orbit of an earlier one stops
  let view = null; // the plane's axes as drawn (lagrangianAxes: the box, X and Y)

  // -- the controls ------------------------------------------------------------------------
  const choice = (label, options) => {
    const select = element("select", { "aria-label": label });
    for (const [value, text] of options) select.append(element("option", { value }, text));
    return select;
  };
  const number = (label, value, placeholder = "") =>
    element("input", { type: "text", "aria-label": label, value, placeholder, size: "7" });
  const coordinateChoice = choice("section coordinate", names.map((q, i) => [String(i), shown(q)]));
  const valueField = number("section value", String(model.initial[names[0]] ?? 0));
  const directionChoice = choice("section direction", [["+", "crossing upwards (+)"], ["-", "crossing downwards (−)"]]);
  const axisChoice = element("select", { "aria-label": "section axis" });
  const kindChoice = choice("section vertical axis", [["velocity", "velocity"], ["momentum", "momentum p = ∂L/∂q̇"]]);
  const energyField = number("section energy", "", "E now");
  const timeField = number("section t_end", String(model.t_end));
  const runButton = element("button", { type: "button" }, "Section of this run");
  const clearButton = element("button", { type: "button" }, "Clear");
  const canvas = element("canvas", { "aria-label": "Poincaré section" });
  const status = element("p", { "aria-live": "polite", "aria-label": "section status" }); // not role=status: the page has one
  // the status line: what was done, or (in red) what was refused and why
  const say = (text, refused = false) => {
    status.textContent = text;
    status.className = refused ? "error" : "";
  };
  const row = (...parts) => {
    const node = element("div", { class: "buttons" });
    for (const part of parts) node.append(typeof part === "string" ? element("span", {}, part) : part);
    return node;
  };
  panel.append(
    row("section", coordinateChoice, "=", valueField, directionChoice),
    row("plane", axisChoice, kindChoice, "E", energyField, "t_end", timeField, runButton, clearButton),
    canvas,
    element("p", { class: "hint" }, "A click in the plane starts an orbit there on the energy shell (E now, or the E typed): the other coordinates and velocities as in the run now, the section's velocity solved from the energy."),
    status,
  );

  function axes() {
    const c = Number(coordinateChoice.value);
    const previous = axisChoice.value;
    axisChoice.replaceChildren(...names.map((q, i) => [i, q]).filter(([i]) => i !== c).map(([i, q]) => element("option", { value: String(i) }, shown(q))));
    if ([...axisChoice.options].some((o) => o.value === previous)) axisChoice.value = previous;
  }
  axes();

  // the section and plane chosen: {c, value, direction, a, kind, tEnd}; throws on a bad field
  function setup() {
    const value = Number(valueField.value);
    const tEnd = Number(timeField.value);
    if (valueField.value.trim() === "" || !Number.isFinite(value)) throw new Error(`the section's value is not a number: '${valueField.value}'`);
    if (!(tEnd > 0 && Number.isFinite(tEnd))) throw new Error(`t_end must be a positive number, not '${timeField.value}'`);
    return { c: Number(coordinateChoice.value), value, direction: directionChoice.value === "-" ? -1 : 1, a: Number(axisChoice.value), kind: kindChoice.value, tEnd };
  }

  const labelOf = (s) => [shown(names[s.a]), s.kind === "momentum" ? `p_${names[s.a]}` : shown(model.coordinates[s.a].velocity)];

  // -- an orbit and its crossings --------------------------------------------------------------
  // the step `last` = {t, y, h, K} of integrators.js, ending at yEnd, as SciPy's DOP853
  // dense output: y(t) on the step
  function interpolant(last, yEnd) {
    const { t, y, h } = last;
    const K = last.K.slice();
    dense.A.forEach((a, r) => {
      const s = K.length;
      const z = y.map((v, i) => {
        let sum = 0;
        for (let j = 0; j < s; j++) sum += a[j] * K[j][i];
        return v + sum * h;
      });
      K.push(system.derivative(t + dense.C[r] * h, z));
    });
    const fOld = K[0];
    const fNew = K[model.dop853.stages];
    const dy = yEnd.map((v, i) => v - y[i]);
    const F = [dy, dy.map((d, i) => h * fOld[i] - d), dy.map((d, i) => 2 * d - h * (fNew[i] + fOld[i]))];
    for (const row of dense.D) F.push(y.map((_, i) => h * row.reduce((sum, d, j) => sum + d * K[j][i], 0)));
    F.reverse();
    return (at) => {
      const x = (at - t) / h;
      const out = y.map(() => 0);
      F.forEach((f, k) => {
        for (let i = 0; i < out.length; i++) out[i] = (out[i] + f[i]) * (k % 2 === 0 ? x : 1 - x);
      });
      return out.map((v, i) => v + y[i]);
    };
  }

  // the crossings {t, y} of the orbit from y0 over [0, tEnd] in the section's direction, as
  // they come: advance(until) steps until the orbit reaches tEnd (true) or the clock
  // (performance.now()) passes `until` (false: call again); found holds the crossings so far
  function crossingsOf(y0, s) {
    const g = (y) => y[s.c] - s.value;
    const steppers = lagrangianIntegrators(model.dop853, n, s.tEnd, system);
    const run = { t: 0, y: y0.slice(), f: null, h: null, p: null, steps: 0 };
    let gOld = g(y0);
    if (gOld === 0) {
      // a start on the section is no crossing: the sign just after it (events.scipy_event)
      const f0 = system.derivative(0, y0);
      const ahead = g(y0.map((v, i) => v + 1e-7 * f0[i]));
      gOld = ahead === 0 ? 0 : Math.sign(ahead) * Number.MIN_VALUE;
    }
    const found = [];
    const advance = (until) => {
      while (run.t < s.tEnd) {
        if (run.steps % 64 === 0 && performance.now() > until) return false;
        step();
      }
      return true;
    };
    const step = () => {
      if (run.steps >= MAX_STEPS) throw new Error(`the orbit took more than ${MAX_STEPS} steps before t = ${s.tEnd}: give a shorter t_end`);
      steppers.dopStep(run, s.tEnd, RTOL, ATOL);
      const gNew = g(run.y);
      const crossed = s.direction > 0 ? gOld <= 0 && gNew >= 0 : gOld >= 0 && gNew <= 0;
      if (crossed) {
        const at = interpolant(run.last, run.y);
        let [a, b] = [run.last.t, run.t];
        let ga = gOld;
        if (ga !== 0) {
          while (b - a > 4 * Number.EPSILON * Math.max(1, Math.abs(b))) {
            const m = a + (b - a) / 2;
            const gm = g(at(m));
            if (gm === 0) [a, b] = [m, m];
            else if (Math.sign(gm) === Math.sign(ga)) [a, ga] = [m, gm];
            else b = m;
          }
        } else b = a;
        const t = a + (b - a) / 2;
        found.push({ t, y: at(t) });
      }
      gOld = gNew;
    };
    return { found, advance, run };
  }

  // the plane's point (u, w) of a state
  const point = (s, t, y) => [y[s.a], s.kind === "momentum" ? system.momenta(t, y)[s.a] : y[n + s.a]];

  // The orbit from y0 integrated in slices of SLICE_MS (the first at once), its points drawn
  // after each, so that the page stays responsive through a long orbit and its points appear
  // as they come; told(orbit) after each slice.  A promise of the orbit when it reached t_end
  // (done), or when the plane was cleared (not done); rejected, the orbit taken off the plane,
  // where it cannot be integrated.
  function addOrbit(s, y0, energy, told) {
    const trace = crossingsOf(y0, s);
    const orbit = { start: y0, energy, crossings: trace.found, points: [], setup: s, done: false, t: 0 };
    orbits.push(orbit);
    const cleared = clears;
    return new Promise((resolve, reject) => {
      const slice = () => {
        if (cleared !== clears) return resolve(orbit);
        let done;
        try {
          done = trace.advance(performance.now() + SLICE_MS);
        } catch (error) {
          if (orbits.includes(orbit)) orbits.splice(orbits.indexOf(orbit), 1);
          draw();
          return reject(error);
        }
        for (const c of trace.found.slice(orbit.points.length)) orbit.points.push(point(s, c.t, c.y));
        orbit.done = done;
        orbit.t = trace.run.t;
        draw();
        told(orbit);
        if (done) resolve(orbit);
        else setTimeout(slice, 0);
      };
      slice();
    });
  }

  // -- the start of an orbit on the energy shell through (u, w) ------------------------------
  function shellStart(s, u, w, E) {
    const y = system.now().y.slice();
    y[s.c] = s.value;
    y[s.a] = u;
    const vc = n + s.c;
    const va = n + s.a;
    const at = (v) => {
      const z = y.slice();
      z[vc] = v;
      if (s.kind === "velocity") {
        z[va] = w;
      } else {
        z[va] = 0;
        const M = system.massMatrix(0, z);
        z[va] = (w - system.momenta(0, z)[s.a]) / M[s.a][s.a];
      }
      return z;
    };
    const [hm, h0, hp, h2] = [-1, 0, 1, 2].map((v) => system.energy(0, at(v)));
    const a = (hm + hp) / 2 - h0;
    const b = (hp - hm) / 2;
    const velocity = shown(model.coordinates[s.c].velocity);
    if (!(a > 0) || Math.abs(4 * a + 2 * b + h0 - h2) > 1e-9 * Math.abs(h2) + 1e-12) {
      throw new Error(`the energy is not a convex quadratic in ${velocity}: it cannot be solved on the shell`);
    }
    const discriminant = b * b - 4 * a * (h0 - E);
    const [labelU, labelW] = labelOf(s);
    const where = `${labelU} = ${u.toPrecision(4)}, ${labelW} = ${w.toPrecision(4)}`;
    if (!(discriminant >= 0)) {
      throw new Error(`outside the energy-allowed region: no real ${velocity} gives E = ${E.toPrecision(6)} at ${where}; nothing started`);
    }
    const root = (-b + s.direction * Math.sqrt(discriminant)) / (2 * a);
    if (!(s.direction * root > 0)) {
      throw new Error(`at ${where} the orbit of E = ${E.toPrecision(6)} does not cross the section ${s.direction > 0 ? "upwards" : "downwards"} (${velocity} = ${root.toPrecision(4)}); nothing started`);
    }
    const start = at(root);
    if (s.kind === "momentum" && Math.abs(system.momenta(0, start)[s.a] - w) > 1e-9 * Math.max(1, Math.abs(w))) {
      throw new Error(`the momentum p_${names[s.a]} is not linear in the velocities here: the start cannot be solved`);
    }
    return start;
  }

  function targetEnergy() {
    const text = energyField.value.trim();
    if (text === "") {
      const now = system.now();
      return system.energy(now.t, now.y);
    }
    const E = Number(text);
    if (!Number.isFinite(E)) throw new Error(`E is not a number: '${energyField.value}'`);
    return E;
  }

  // the orbit's status: its crossings so far while it runs (where it is), then in all
  const progress = (text, orbit) => say(orbit.done ? `${text}.` : `${text} so far (t = ${orbit.t.toPrecision(3)})…`);

  // the orbit through the plane's point (u, w): a promise of it (see addOrbit); throws where
  // no orbit starts there
  function launch(u, w) {
    const s = setup();
    const E = targetEnergy();
    const start = shellStart(s, u, w, E);
    const [labelU, labelW] = labelOf(s);
    const text = `Orbit ${orbits.length + 1} from ${labelU} = ${u.toPrecision(4)}, ${labelW} = ${w.toPrecision(4)} at E = ${E.toPrecision(6)}`;
    return track(addOrbit(s, start, E, (orbit) => progress(`${text}: ${orbit.points.length} crossings`, orbit)));
  }

  function fromRun() {
    const s = setup();
    const start = system.start();
    return track(addOrbit(s, start, system.energy(0, start), (orbit) => progress(`The run's orbit: ${orbit.points.length} crossings up to t = ${s.tEnd}`, orbit)));
  }

  // the promise of an orbit, kept until it settles (settled() waits for them all)
  function track(promise) {
    const kept = promise.catch(() => null);
    running.add(kept);
    kept.then(() => running.delete(kept));
    return promise;
  }

  function clear() {
    clears += 1;
    orbits.length = 0;
    draw();
  }

  // -- the plane -------------------------------------------------------------------------
  function draw() {
    let s = null;
    try {
      s = setup();
    } catch (error) {
      // a setting that cannot be read: the plane is left empty (the run says why)
    }
    const all = s === null ? [] : orbits.flatMap((o) => o.points);
    if (s !== null && !all.length) {
      // no points yet: the plane about the run's state of the moment
      const now = system.now();
      all.push(...[-1, 1].map((d) => point(s, now.t, now.y).map((v) => v + d)));
    }
    const [labelU, labelW] = s === null ? ["", ""] : labelOf(s);
    const range = (xa, xb) => `${labelU}   (${xa.toPrecision(3)} to ${xb.toPrecision(3)})`;
    const frame = lagrangianAxes(canvas, all.map((p) => p[0]), all.map((p) => p[1]), [range, labelW], 40);
    if (frame === null) return;
    view = frame;
    orbits.forEach((orbit, k) => {
      frame.c.fillStyle = COLORS[k % COLORS.length];
      for (const [u, w] of orbit.points) {
        const [x, y] = screen(u, w);
        frame.c.fillRect(x - 1, y - 1, 2, 2);
      }
    });
  }

  // CSS pixels on the canvas of (u, w), and back
  function screen(u, w) {
    return [view.X(u), view.Y(w)];
  }
  function plane(x, y) {
    const { xa, xb, ya, yb, width, height, pad } = view;
    return [xa + ((x - pad) / (width - pad - 6)) * (xb - xa), ya + ((height - pad + 6 - y) / (height - pad)) * (yb - ya)];
  }

  // an action of the panel's controls: what it refuses, at once or as its orbit runs, said
  const said = (action) => (event) => {
    try {
      const orbit = action(event);
      if (orbit instanceof Promise) orbit.catch((error) => say(error.message, true));
    } catch (error) {
      say(error.message, true);
    }
  };
  canvas.addEventListener(
    "click",
    said((event) => {
      if (view === null) draw();
      const box = canvas.getBoundingClientRect();
      return launch(...plane(event.clientX - box.left, event.clientY - box.top));
    }),
  );
  runButton.addEventListener("click", said(fromRun));
  clearButton.addEventListener("click", () => {
    clear();
    say("");
  });
  // another section or plane: the points drawn belong to the old one
  coordinateChoice.addEventListener("change", () => {
    axes();
    valueField.value = String(model.initial[names[Number(coordinateChoice.value)]] ?? 0);
    clear();
  });
  for (const control of [valueField, directionChoice, axisChoice, kindChoice, timeField]) control.addEventListener("change", () => clear());

  // the hook (window.lagrangian.section) for scripts and tests
  const hook = Object.freeze({
    // choose the section and plane: {coordinate, value, direction, axis, kind, energy, t_end}
    configure(options) {
      if ("coordinate" in options) {
        coordinateChoice.value = String(names.indexOf(options.coordinate));
        axes();
      }
      if ("value" in options) valueField.value = String(options.value);
      if ("direction" in options) directionChoice.value = options.direction;
      if ("axis" in options) axisChoice.value = String(names.indexOf(options.axis));
      if ("kind" in options) kindChoice.value = options.kind;
      if ("energy" in options) energyField.value = options.energy === null ? "" : String(options.energy);
      if ("t_end" in options) timeField.value = String(options.t_end);
      clear();
    },
    // the run's orbit, when integrated (a promise)
    fromRun: async () => summary(await fromRun()),
    // the orbit started at (u, w) when integrated, or {refused: why} (said in the status line
    // as well): a promise
    async launch(u, w) {
      try {
        return summary(await launch(u, w));
      } catch (error) {
        say(error.message, true);
        return { refused: error.message };
      }
    },
    // the orbits as drawn now (one being integrated: done false, its points so far)
    orbits: () => orbits.map(summary),
    // a promise resolved when no orbit is being integrated
    settled: () => Promise.all([...running]).then(() => undefined),
    clear,
    screen: (u, w) => (view === null ? null : screen(u, w)),
    status: () => status.textContent,
  });
  const summary = (orbit) => ({ start: orbit.start.slice(), energy: orbit.energy, points: orbit.points.map((p) => p.slice()), times: orbit.crossings.map((c) => c.t), states: orbit.crossings.map((c) => c.y.slice()), done: orbit.done });
  return { panel, hook, clear, draw };
}
