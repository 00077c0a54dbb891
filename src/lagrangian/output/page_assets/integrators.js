// The page's integrators (lagrangian page), one step at a time of a run {t, y, f, h, p, steps}.
//
// "dop853": Dormand and Prince's explicit Runge-Kutta pair of order 8(5,3) with SciPy's
// error norm and step-size control (Hairer, Norsett & Wanner, Solving ODE I, 2nd ed.,
// II.10; scipy.integrate.DOP853); the coefficients `tab` are SciPy's, given by the page
// writer, so that the page steps as `lagrangian simulate --method dop853` does.
// "variational": the midpoint discrete Lagrangian (Marsden & West, Acta Numerica 10
// (2001), 2.2, with the forces of 3.2) in position-momentum form, as
// lagrangian.integrate.variational:
//   p_k = L_q'(q_m, v) - (h/2)[L_q + Q](q_m, v),  q_m = q_k + h v / 2,
//   q_{k+1} = q_k + h v,  p_{k+1} = p_k + h [L_q + Q](q_m, v),
// solved for v by Newton's method with M as the Jacobian (symplectic: the energy error
// stays bounded over long runs; the momentum of a cyclic coordinate is kept exactly).
//
// system: derivative(t, y) -> y' = [q', q'']; momentaAndForces(t, y) -> [p, L_q + Q];
// massMatrix(t, y) -> M; solve(K, r) -> x of K x = r (the generated module's).
function lagrangianIntegrators(tab, n, span, system) {
  "use strict";
  const rms = (x) => Math.sqrt(x.reduce((s, v) => s + v * v, 0) / Math.max(1, x.length));

  // -- Dormand-Prince 8(5,3), SciPy's step control --------------------------------------
  const SAFETY = 0.9;
  const MIN_FACTOR = 0.2;
  const MAX_FACTOR = 10;
  const EXPONENT = -1 / 8;

  function initialStep(t, y, f, rtol, atol, span) {
    const scale = y.map((v) => atol + Math.abs(v) * rtol);
    const d0 = rms(y.map((v, i) => v / scale[i]));
    const d1 = rms(f.map((v, i) => v / scale[i]));
    let h0 = d0 < 1e-5 || d1 < 1e-5 ? 1e-6 : (0.01 * d0) / d1;
    h0 = Math.min(h0, span);
    const f1 = system.derivative(t + h0, y.map((v, i) => v + h0 * f[i]));
    const d2 = rms(f1.map((v, i) => (v - f[i]) / scale[i])) / h0;
    const h1 =
      d1 <= 1e-15 && d2 <= 1e-15 ? Math.max(1e-6, h0 * 1e-3) : (0.01 / Math.max(d1, d2)) ** (1 / 8);
    return Math.min(100 * h0, h1, span);
  }

  function rkStep(t, y, f, h) {
    const K = [f];
    for (let s = 1; s < tab.stages; s++) {
      const a = tab.A[s];
      const z = y.slice();
      for (let i = 0; i < y.length; i++) {
        let sum = 0;
        for (let j = 0; j < s; j++) sum += a[j] * K[j][i];
        z[i] += h * sum;
      }
      K.push(system.derivative(t + tab.C[s] * h, z));
    }
    const yNew = y.map((v, i) => {
      let sum = 0;
      for (let j = 0; j < tab.stages; j++) sum += tab.B[j] * K[j][i];
      return v + h * sum;
    });
    const fNew = system.derivative(t + h, yNew);
    K.push(fNew);
    return [yNew, fNew, K];
  }

  function errorNorm(K, h, scale) {
    let e5 = 0;
    let e3 = 0;
    for (let i = 0; i < scale.length; i++) {
      let s5 = 0;
      let s3 = 0;
      for (let j = 0; j < K.length; j++) {
        s5 += tab.E5[j] * K[j][i];
        s3 += tab.E3[j] * K[j][i];
      }
      e5 += (s5 / scale[i]) ** 2;
      e3 += (s3 / scale[i]) ** 2;
    }
    if (e5 === 0 && e3 === 0) return 0;
    return (Math.abs(h) * e5) / Math.sqrt((e5 + 0.01 * e3) * scale.length);
  }

  // One accepted step of `run` (a state {t, y, f, h, steps}) that ends at tEnd at the latest.
  function dopStep(run, tEnd, rtol, atol) {
    if (run.f === null) run.f = system.derivative(run.t, run.y);
    if (run.h === null) run.h = initialStep(run.t, run.y, run.f, rtol, atol, span);
    let hAbs = run.h;
    let rejected = false;
    for (;;) {
      const minStep = 10 * Number.EPSILON * Math.max(1, Math.abs(run.t));
      if (!(hAbs >= minStep)) throw new Error("the step size became too small (a singularity?)");
      const clipped = run.t + hAbs >= tEnd;
      const h = clipped ? tEnd - run.t : hAbs;
      const [yNew, fNew, K] = rkStep(run.t, run.y, run.f, h);
      const scale = run.y.map((v, i) => atol + Math.max(Math.abs(v), Math.abs(yNew[i])) * rtol);
      const error = errorNorm(K, h, scale);
      if (error < 1 && yNew.every(Number.isFinite)) {
        let factor = error === 0 ? MAX_FACTOR : Math.min(MAX_FACTOR, SAFETY * error ** EXPONENT);
        if (rejected) factor = Math.min(1, factor);
        // the step just taken, for its dense output (section.js): K holds f at its end
        run.last = { t: run.t, y: run.y, h, K };
        // a step shortened to land on tEnd does not shorten the next one
        run.h = clipped ? Math.max(hAbs, h * factor) : h * factor;
        run.t = clipped ? tEnd : run.t + h;
        run.y = yNew;
        run.f = fNew;
        run.steps += 1;
        return;
      }
      hAbs = Math.min(hAbs, h) * Math.max(MIN_FACTOR, Number.isFinite(error) ? SAFETY * error ** EXPONENT : MIN_FACTOR);
      rejected = true;
    }
  }

  // -- the variational midpoint integrator --------------------------------------------
  const momenta = (t, y) => system.momentaAndForces(t, y)[0];

  // Newton's iteration x -> x - J(x)^-1 r(x) until |r| <= 1e-14 scale, or until an update
  // no longer halves the residual (rounding reached)
  function newtonSolve(residual, jacobianAt, x, scale) {
    let previous = Infinity;
    for (let k = 0; k < 50; k++) {
      const r = residual(x);
      const size = Math.max(...r.map(Math.abs));
      if (size <= 1e-14 * scale || (k > 2 && size > previous / 2)) return x;
      previous = size;
      const dx = system.solve(jacobianAt(x), r.map((v) => -v));
      x = x.map((v, i) => v + dx[i]);
    }
    return x;
  }

  function midpointStep(run, h) {
    const q = run.y.slice(0, n);
    if (run.p === null) run.p = momenta(run.t, run.y);
    const pk = run.p;
    const tm = run.t + h / 2;
    const mid = (v) => [...q.map((x, i) => x + (h / 2) * v[i]), ...v];
    const scale = Math.max(1, ...pk.map(Math.abs));
    const v = newtonSolve(
      (w) => {
        const [p, F] = system.momentaAndForces(tm, mid(w));
        return p.map((x, i) => x - (h / 2) * F[i] - pk[i]);
      },
      (w) => system.massMatrix(tm, mid(w)),
      run.y.slice(n),
      scale,
    );
    const F = system.momentaAndForces(tm, mid(v))[1];
    const qNew = q.map((x, i) => x + h * v[i]);
    const pNew = pk.map((x, i) => x + h * F[i]);
    const tNew = run.t + h;
    const rate = newtonSolve(
      (w) => momenta(tNew, [...qNew, ...w]).map((x, i) => x - pNew[i]),
      (w) => system.massMatrix(tNew, [...qNew, ...w]),
      v,
      scale,
    );
    if (![...qNew, ...rate].every(Number.isFinite)) throw new Error("the motion left the numbers");
    run.t = tNew;
    run.y = [...qNew, ...rate];
    run.p = pNew;
    run.f = null;
    run.steps += 1;
  }

  return { dopStep, midpointStep };
}
