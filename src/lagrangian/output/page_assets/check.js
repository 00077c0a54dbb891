// The checker of the exercise page: an answer against the right one, as `lagrangian check`
// does it (lagrangian/analysis/check): the same numerical identity tests at seeded random
// points and the same term-by-term split (expressions.js), so that the verdicts and the
// terms at fault agree.

const EXERCISE_SETS = 3; // parameter sets (lagrangian.analysis.check.sampling.PARAMETER_SETS)
const EXERCISE_STATES = 5; // states per set (STATES)
const EXERCISE_TOLERANCE = 1e-7; // relative tolerance of every comparison (TOLERANCE)

// -- points and comparisons (lagrangian.analysis.check.sampling) -------------------------------
function exercisePoints(names) {
  let seed = 20261129;
  const random = () => { // mulberry32
    seed = (seed + 0x6d2b79f5) | 0;
    let x = Math.imul(seed ^ (seed >>> 15), 1 | seed);
    x = (x + Math.imul(x ^ (x >>> 7), 61 | x)) ^ x;
    return ((x ^ (x >>> 14)) >>> 0) / 4294967296;
  };
  const uniform = (lo, hi) => lo + (hi - lo) * random();
  const signed = () => (random() < 0.5 ? -1 : 1);
  const envs = [];
  for (let p = 0; p < EXERCISE_SETS; p++) {
    const parameters = {};
    for (const { name, positive } of names.parameters) parameters[name] = uniform(0.5, 2) * (positive ? 1 : signed());
    const row = [];
    for (let s = 0; s < EXERCISE_STATES; s++) {
      const env = { ...parameters };
      for (const name of names.state) env[name] = uniform(0.2, 1.4) * signed();
      row.push(env);
    }
    envs.push(row);
  }
  return envs;
}

const exMap = (a, b, fn) => a.map((row, p) => row.map((x, s) => fn(x, b === null ? null : Array.isArray(b) ? (b[p].length === 1 ? b[p][0] : b[p][s]) : b)));
const exFinite = (x) => Number.isFinite(x);

function exerciseClose(a, b, scale = 0) {
  const columns = Math.max(a[0].length, Array.isArray(b) ? b[0].length : 1);
  for (let p = 0; p < a.length; p++) {
    let finite = 0;
    for (let s = 0; s < columns; s++) {
      const pick = (v) => (Array.isArray(v) ? (v[p].length === 1 ? v[p][0] : v[p][s]) : v);
      const x = pick(a), y = pick(b), z = pick(scale);
      if (!exFinite(x) || !exFinite(y)) continue;
      finite++;
      if (Math.abs(x - y) > EXERCISE_TOLERANCE * (Math.abs(x) + Math.abs(y) + Math.abs(z)) + 1e-300) return false;
    }
    if (finite < Math.min(2, columns)) return false;
  }
  return true;
}

function exerciseMedian(row) {
  const values = row.filter(exFinite).sort((x, y) => x - y);
  if (!values.length) return NaN;
  const middle = values.length >> 1;
  return values.length % 2 ? values[middle] : (values[middle - 1] + values[middle]) / 2;
}

const exPerSet = (values) => values.map((row) => [exerciseMedian(row)]);
const exStateFree = (values, scale = 0) => exerciseClose(values, exPerSet(values), scale);
const exAbs = (values) => values.map((row) => row.map((x) => (exFinite(x) ? Math.abs(x) : 0)));

// -- groups and the diagnosis (lagrangian.analysis.check.terms) --------------------------------
function exerciseChecker(data) {
  const envs = exercisePoints(data.names);
  const state = new Set(data.names.state);
  const accelerations = new Set(data.names.coordinates.map((c) => c.acceleration));
  const known = new Set([...data.names.state, ...data.names.parameters.map((p) => p.name)]);
  const at = (tree) => envs.map((row) => row.map((env) => {
    const v = exerciseValue(tree, env);
    return exFinite(v) ? v : NaN;
  }));
  const zeros = () => envs.map((row) => row.map(() => 0));

  function studentGroups(tree) {
    const found = [];
    for (const term of exerciseExpand(tree)) {
      const merged = new Map();
      for (const [f, e] of term.factors) {
        const key = JSON.stringify(f);
        merged.set(key, [f, (merged.get(key)?.[1] ?? 0) + e]);
      }
      const factors = [...merged.values()].filter(([, e]) => e !== 0);
      const keyFactors = factors.filter(([f]) => [...exerciseSymbols(f)].some((n) => state.has(n)));
      const coefficientFactors = factors.filter((x) => !keyFactors.includes(x));
      const power = ([f, e]) => (e === 1 ? f : ["^", f, ["n", e]]);
      const keyTree = ["*", ["n", 1], ...keyFactors.map(power)];
      const coefficientTree = ["*", ["n", term.c], ...coefficientFactors.map(power)];
      const text = exercisePrinted(term.c, factors);
      const monomial = { c: term.c, factors, coefficient: exercisePrinted(term.c, coefficientFactors) };
      add(found, keyTree, at(keyTree), exPerSet(at(coefficientTree)), text, keyFactors, monomial);
    }
    return finish(found);
  }

  function add(found, key, keyValues, coefficientValues, text, keyFactors, monomial) {
    const size = exAbs(exMap(keyValues, coefficientValues, (k, c) => k * c));
    for (const g of found) {
      const ratio = exMap(keyValues, g.keyValues, (x, y) => x / y);
      if (exStateFree(ratio)) {
        g.coefficientValues = exMap(g.coefficientValues, exMap(coefficientValues, exPerSet(ratio), (c, r) => c * r), (x, y) => x + y);
        g.scale = exMap(g.scale, size, (x, y) => x + y);
        g.texts.push(text);
        g.monomial = null;
        return;
      }
    }
    const symbols = new Set(keyFactors.flatMap(([f]) => [...exerciseSymbols(f)]));
    found.push({ key, keyValues, coefficientValues, scale: size, texts: [text], symbols, monomial });
  }

  function finish(found) {
    return found
      .filter((g) => !exerciseClose(exMap(g.keyValues, g.coefficientValues, (k, c) => k * c), zeros(), g.scale))
      .map((g) => ({ ...g, printed: g.texts.join(" + ").replace(/\+ -/g, "- ") }));
  }

  function rightGroups(answer) {
    return answer.groups.map((g) => {
      const keyValues = at(g.key);
      const value = at(g.value);
      return {
        key: g.key, keyValues, printed: g.printed.replace(/\*\*/g, "^"), coefficient: g.coefficient.replace(/\*\*/g, "^"),
        coefficientValues: exPerSet(exMap(value, keyValues, (v, k) => v / k)),
        scale: exAbs(value), symbols: exerciseSymbols(g.key), monomial: g.monomial,
      };
    });
  }

  const moving = (groups) => groups.filter((g) => !exStateFree(g.keyValues));
  const totalScale = (groups) => groups.reduce((sum, g) => exMap(sum, g.scale, (x, y) => x + y), zeros());

  function compare(given, right, rescale = false, leading = new Set()) {
    const unit = envs.map((row) => row.map(() => 1));
    if (!rescale || !given.length || !right.length) return matched(given, right, unit, null);
    const led = leading.size ? factors(given, right, leading) : [];
    const candidates = led.length ? led : factors(given, right, new Set()).filter((c) => exStateFree(c.values));
    let best = matched(given, right, unit, null);
    let bestRank = null;
    for (const c of candidates) {
      const comparison = matched(given, right, c.values, c.unit ? null : c);
      if (!led.length && comparison.ok < 2) continue; // one term alike is no evidence of a scale
      const rank = [comparison.ok, -comparison.problems.length];
      if (bestRank === null || rank[0] > bestRank[0] || (rank[0] === bestRank[0] && rank[1] > bestRank[1])) {
        best = comparison;
        bestRank = rank;
      }
    }
    return best;
  }

  function factors(given, right, leading) {
    const found = [];
    const leadingOf = (g) => [...g.symbols].filter((n) => leading.has(n)).sort().join(",");
    for (const mine of given) {
      for (const theirs of right) {
        if (leading.size && (!leadingOf(theirs) || leadingOf(theirs) !== leadingOf(mine))) continue;
        const values = exMap(
          exMap(mine.keyValues, mine.coefficientValues, (k, c) => k * c),
          exMap(theirs.keyValues, theirs.coefficientValues, (k, c) => k * c),
          (x, y) => x / y,
        );
        found.push({ values, unit: exerciseClose(values, 1), mine, theirs });
      }
    }
    return found;
  }

  // `scaled`: null, or the pair of terms whose ratio the right terms are multiplied by
  function matched(given, right, factor, scaled) {
    const left = [...right];
    const pairs = [];
    const extra = [];
    for (const g of given) {
      const k = left.findIndex((candidate) => exStateFree(exMap(exMap(g.keyValues, candidate.keyValues, (x, y) => x / y), factor, (x, f) => x / f)));
      if (k < 0) { extra.push(g); continue; }
      const [candidate] = left.splice(k, 1);
      const ratio = exMap(exMap(g.keyValues, candidate.keyValues, (x, y) => x / y), factor, (x, f) => x / f);
      pairs.push([g, candidate, exMap(g.coefficientValues, exPerSet(ratio), (c, r) => c * r)]);
    }
    const expected = (g) => (scaled === null ? g.printed : exerciseScaled(g, scaled.mine, scaled.theirs));
    const problems = [];
    let ok = 0;
    for (const [student, right, mine] of pairs) {
      const theirs = right.coefficientValues;
      if (exerciseClose(mine, theirs)) ok++;
      else if (exerciseClose(mine, exMap(theirs, null, (x) => -x))) problems.push({ term: student.printed, problem: "sign", expected: expected(right) });
      else problems.push({ term: student.printed, problem: "factor", expected: expected(right) });
    }
    for (const g of left) problems.push({ term: expected(g), problem: "missing", expected: expected(g) });
    for (const g of extra) problems.push({ term: g.printed, problem: "extra", expected: null });
    return { problems, ok };
  }

  // -- the answers (lagrangian.analysis.check.answers) ----------------------------------------
  const sentence = (t) => ({
    missing: `the term ${t.term} is missing`,
    extra: `the term ${t.term} should not be there`,
    sign: `the term ${t.term} has the wrong sign: it should be ${t.expected}`,
    factor: `the term ${t.term} should be ${t.expected}`,
  })[t.problem];
  const wrong = (problems, prefix = "") => ({
    verdict: "wrong",
    reason: prefix + (problems.map(sentence).join("; ") || "it differs from the right one"),
    terms: problems,
  });
  const right = (reason = "right") => ({ verdict: "right", reason, terms: [] });
  const equivalent = (reason) => ({ verdict: "equivalent", reason, terms: [] });

  function byTerms(tree, answer) {
    let mine = studentGroups(tree);
    let theirs = rightGroups(answer);
    if (answer.up_to_constant) {
      mine = moving(mine);
      theirs = moving(theirs);
    }
    const scale = totalScale([...mine, ...theirs]);
    const difference = exMap(at(tree), at(answer.tree), (x, y) => x - y);
    if (exerciseClose(difference, zeros(), scale)) return right();
    if (answer.up_to_constant && exStateFree(difference, scale)) return equivalent("right up to a constant, which changes no motion");
    return wrong(compare(mine, theirs).problems);
  }

  function eulerLagrange(tree) {
    return data.names.coordinates.map((c) => {
      const momentum = exerciseDiff(tree, c.velocity);
      const parts = [exerciseDiff(momentum, "t")];
      for (const d of data.names.coordinates) {
        parts.push(["*", exerciseDiff(momentum, d.name), ["s", d.velocity]]);
        parts.push(["*", exerciseDiff(momentum, d.velocity), ["s", d.acceleration]]);
      }
      parts.push(["*", ["n", -1], exerciseDiff(tree, c.name)]);
      return ["+", ...parts];
    });
  }

  function lagrangian(tree) {
    const plain = byTerms(tree, data.lagrangian);
    if (plain.verdict !== "wrong") return plain;
    const mine = eulerLagrange(tree).map(at);
    const theirs = data.lagrangian.euler_lagrange.map(at);
    const stack = (parts) => envs.map((row, p) => parts.flatMap((part) => part[p]));
    const m = stack(mine), r = stack(theirs);
    const largest = Math.max(0, ...r.flat().filter(exFinite).map(Math.abs));
    const ratio = m.map((row, p) => row.map((x, s) => (Math.abs(r[p][s]) > 1e-9 * largest ? x / r[p][s] : NaN)));
    const factor = exPerSet(ratio);
    if (factor.some(([f]) => !exFinite(f) || Math.abs(f) < 1e-9)) return plain;
    const scale = exMap(exPerSet(exAbs(r)), factor, (x, f) => x * Math.abs(f));
    if (!exerciseClose(m, exMap(r, factor, (x, f) => x * f), scale)) return plain;
    if (exerciseClose(factor, 1)) return equivalent("right up to a total time derivative: the same equations of motion");
    const same = factor.every(([f]) => exerciseClose([[f]], factor[0][0]));
    const shown = same ? exerciseNumber(factor[0][0]) : "c";
    let how = `the constant factor ${shown} and a total time derivative`;
    if (same) {
      const difference = exMap(at(tree), exMap(at(data.lagrangian.tree), factor, (x, f) => x * f), (x, y) => x - y);
      if (exerciseClose(difference, zeros(), exAbs(at(tree)))) how = `the constant factor ${shown}`;
    }
    return equivalent(`right up to ${how}: the same equations of motion`);
  }

  function equation(tree) {
    const coordinates = data.names.coordinates;
    const value = at(tree);
    for (const [i, answer] of data.equations.entries()) {
      for (const reference of [answer.tree, answer.shown]) {
        for (const sign of [1, -1]) {
          const difference = exMap(value, at(reference), (x, y) => x - sign * y);
          if (exerciseClose(difference, zeros(), exAbs(value))) return right(`right: the equation of ${coordinates[i].name}`);
        }
      }
    }
    const used = combination(tree, value);
    if (used.length === 1) return equivalent(`right up to a factor: the equation of ${coordinates[used[0]].name} times ${equationFactor(tree, used[0])}`);
    if (used.length > 1) return equivalent(`right: a combination of the equations of ${used.map((i) => coordinates[i].name).join(" and ")}`);
    const mine = studentGroups(tree);
    let best = null;
    for (const [i, answer] of data.equations.entries()) {
      const comparison = compare(mine, rightGroups(answer), true, accelerations);
      const rank = [comparison.ok, -comparison.problems.length];
      if (best === null || rank[0] > best.rank[0] || (rank[0] === best.rank[0] && rank[1] > best.rank[1])) best = { rank, i, comparison };
    }
    if (best.comparison.ok === 0) {
      return { verdict: "wrong", reason: `not related to the equations of motion (of ${coordinates.map((c) => c.name).join(", ")})`, terms: [] };
    }
    return wrong(best.comparison.problems, `the equation of ${coordinates[best.i].name} with errors (all terms on the left): `);
  }

  // the factor of an equation that is the right one times it: the ratio of the two
  // acceleration terms, printed where both are products
  function equationFactor(tree, index) {
    const leading = (g) => [...g.symbols].filter((n) => accelerations.has(n)).sort().join(",");
    const one = { monomial: { c: 1, factors: [] }, printed: "1" };
    for (const mine of studentGroups(tree).filter(leading)) {
      for (const theirs of rightGroups(data.equations[index])) {
        if (leading(theirs) !== leading(mine) || !mine.monomial) continue;
        if (theirs.monomial) return exerciseScaled(one, mine, theirs);
        // the same key: the ratio of the coefficients, written out
        if (exerciseClose(exMap(mine.keyValues, theirs.keyValues, (x, y) => x / y), 1)) {
          return `${mine.monomial.coefficient}/(${theirs.coefficient})`;
        }
      }
    }
    return "a factor";
  }

  function combination(tree, value) {
    const names = data.names.coordinates.map((c) => c.acceleration);
    const rest = (t) => envs.map((row) => row.map((env) => exerciseValue(t, { ...env, ...Object.fromEntries(names.map((n) => [n, 0])) })));
    const rows = (t) => [...names.map((n) => at(exerciseDiff(t, n))), rest(t)];
    const mine = rows(tree);
    const linear = exMap(value, envs.map((row, p) => row.map((env, s) => mine[names.length][p][s] + names.reduce((sum, n, j) => sum + mine[j][p][s] * env[n], 0))), (x, y) => x - y);
    if (!exerciseClose(linear, zeros(), exAbs(value))) return [];
    const theirs = data.equations.map((answer) => rows(answer.tree));
    const used = new Array(theirs.length).fill(false);
    for (let p = 0; p < EXERCISE_SETS; p++) {
      for (let s = 0; s < EXERCISE_STATES; s++) {
        const a = theirs.map((r) => r.map((column) => column[p][s])); // n equations x (n + 1)
        const b = mine.map((column) => column[p][s]);
        if (![...a.flat(), ...b].every(exFinite)) continue;
        const size = Math.max(...b.map(Math.abs));
        if (size === 0) return [];
        const weights = exerciseLeastSquares(a, b);
        if (weights === null) return [];
        const largestA = Math.max(...a.flat().map(Math.abs));
        const largestW = Math.max(...weights.map(Math.abs));
        const residual = Math.max(...b.map((x, k) => Math.abs(weights.reduce((sum, w, i) => sum + w * a[i][k], 0) - x)));
        if (residual > 1e-7 * (size + largestA * largestW)) return [];
        weights.forEach((w, i) => { if (Math.abs(w) > 1e-9 * largestW) used[i] = true; });
      }
    }
    return used.flatMap((u, i) => (u ? [i] : []));
  }

  const steps = {
    kinetic: (tree) => byTerms(tree, data.kinetic),
    potential: (tree) => byTerms(tree, data.potential),
    lagrangian,
    equations: equation,
  };

  return {
    // an answer's verdict, reason and terms; a bad text gives {verdict: "error", reason}
    check(step, text) {
      if (!(step in steps) || !(step === "equations" ? data.equations : data[step])) throw new Error(`no such step in this exercise: ${step}`);
      try {
        let tree;
        const sides = text.split("=");
        if (step !== "equations" || sides.length === 1) tree = exerciseParse(text, known);
        else if (sides.length > 2 || sides.some((side) => !side.trim())) throw new Error("an equation is 'lhs = rhs' or one expression (= 0)");
        else { // each side read with the other blanked out, as check does: positions in the whole text
          const [lhs, rhs] = sides;
          tree = ["+", exerciseParse(lhs + " ".repeat(rhs.length + 1), known), ["*", ["n", -1], exerciseParse(" ".repeat(lhs.length + 1) + rhs, known)]];
        }
        return steps[step](tree);
      } catch (error) {
        return { verdict: "error", reason: error.message, terms: [] };
      }
    },
  };
}

// the least-squares weights w of sum_i w_i a_i = b (normal equations, partial pivoting)
function exerciseLeastSquares(a, b) {
  const n = a.length;
  const matrix = a.map((row) => [...a.map((other) => row.reduce((sum, x, k) => sum + x * other[k], 0)), row.reduce((sum, x, k) => sum + x * b[k], 0)]);
  for (let col = 0; col < n; col++) {
    let pivot = col;
    for (let r = col + 1; r < n; r++) if (Math.abs(matrix[r][col]) > Math.abs(matrix[pivot][col])) pivot = r;
    if (matrix[pivot][col] === 0) return null;
    [matrix[col], matrix[pivot]] = [matrix[pivot], matrix[col]];
    for (let r = 0; r < n; r++) {
      if (r === col) continue;
      const f = matrix[r][col] / matrix[col][col];
      for (let k = col; k <= n; k++) matrix[r][k] -= f * matrix[col][k];
    }
  }
  return matrix.map((row, i) => row[n] / row[i]);
}

// the right term g times mine / theirs, in the student's scale: one product where all three are
// products (factors with the same tree combined), else the quotient written out
function exerciseScaled(g, mine, theirs) {
  if (!(g.monomial && mine.monomial && theirs.monomial)) return `(${g.printed})*(${mine.printed})/(${theirs.printed})`;
  const merged = new Map();
  const put = (factors, sign) => {
    for (const [f, e] of factors) {
      const key = JSON.stringify(f);
      merged.set(key, [f, (merged.get(key)?.[1] ?? 0) + sign * e]);
    }
  };
  put(g.monomial.factors, 1);
  put(mine.monomial.factors, 1);
  put(theirs.monomial.factors, -1);
  const factors = [...merged.values()].filter(([, e]) => Math.abs(e) > 1e-12);
  return exercisePrinted((g.monomial.c * mine.monomial.c) / theirs.monomial.c, factors);
}
