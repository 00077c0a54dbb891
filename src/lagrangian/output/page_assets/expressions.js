// Expressions of the exercise page (exercise.js): the student's text parsed into a tree
// (never evaluated as code), its values, derivatives and term-by-term expansion, and the
// printing of a term.  The right answers come from Python as trees of the same form
// (lagrangian/output/exercise.py):
//   ["n", 2.5]  ["s", "theta"]  ["+", a, ...]  ["*", a, ...]  ["^", base, exponent]
//   ["f", "cos", argument, ...]

const EXERCISE_MAX_TERMS = 500; // an expansion larger than this is refused (check's MAX_TERMS)
const EXERCISE_MAX_POWER = 6; // a sum to a larger power is kept whole (check's MAX_POWER)

// -- the parser -------------------------------------------------------------------------------
const EXERCISE_FUNCTIONS = {
  sin: 1, cos: 1, tan: 1, cot: 1, sec: 1, csc: 1, asin: 1, acos: 1, atan: 1, atan2: 2,
  sinh: 1, cosh: 1, tanh: 1, exp: 1, log: 1, sqrt: 1, Abs: 1, sign: 1,
};

function exerciseParse(text, known) {
  const tokens = [];
  const pattern = /\s*(?:(\d+\.?\d*(?:[eE][+-]?\d+)?|\.\d+(?:[eE][+-]?\d+)?)|([A-Za-z][A-Za-z0-9_]*)|(\*\*|[-+*/^(),]))/y;
  let at = 0;
  while (at < text.length) {
    if (/^\s*$/.test(text.slice(at))) break;
    pattern.lastIndex = at;
    const found = pattern.exec(text);
    if (!found) throw new Error(`unexpected character '${text.slice(at).trim()[0]}' at position ${at + text.slice(at).search(/\S/) + 1}`);
    const start = found.index + found[0].search(/\S/);
    if (found[1] !== undefined) tokens.push({ kind: "number", value: Number(found[1]), at: start });
    else if (found[2] !== undefined) tokens.push({ kind: "name", value: found[2], at: start });
    else tokens.push({ kind: found[3] === "**" ? "^" : found[3], at: start });
    at = pattern.lastIndex;
  }
  tokens.push({ kind: "end", at: text.length });
  let index = 0;
  const peek = () => tokens[index];
  const where = (token) => `at position ${token.at + 1}`;
  const expect = (kind) => {
    const token = tokens[index++];
    if (token.kind !== kind) throw new Error(`expected '${kind}' ${where(token)}`);
    return token;
  };
  function sum() {
    const terms = [product()];
    while (peek().kind === "+" || peek().kind === "-") {
      const negative = tokens[index++].kind === "-";
      const term = product();
      terms.push(negative ? ["*", ["n", -1], term] : term);
    }
    return terms.length === 1 ? terms[0] : ["+", ...terms];
  }
  function product() {
    const factors = [unary()];
    while (peek().kind === "*" || peek().kind === "/") {
      const divide = tokens[index++].kind === "/";
      const factor = unary();
      factors.push(divide ? ["^", factor, ["n", -1]] : factor);
    }
    return factors.length === 1 ? factors[0] : ["*", ...factors];
  }
  function unary() {
    if (peek().kind === "-") {
      index++;
      return ["*", ["n", -1], unary()];
    }
    if (peek().kind === "+") {
      index++;
      return unary();
    }
    return power();
  }
  function power() {
    const base = primary();
    if (peek().kind !== "^") return base;
    index++;
    return ["^", base, unary()];
  }
  function primary() {
    const token = tokens[index++];
    if (token.kind === "number") return ["n", token.value];
    if (token.kind === "(") {
      const inside = sum();
      expect(")");
      return inside;
    }
    if (token.kind !== "name") {
      throw new Error(token.kind === "end" ? "unexpected end of expression" : `unexpected '${token.kind}' ${where(token)}`);
    }
    const name = token.value;
    if (peek().kind === "(") {
      if (!(name in EXERCISE_FUNCTIONS)) throw new Error(`unknown function '${name}' ${where(token)}`);
      index++;
      const args = [sum()];
      while (peek().kind === ",") {
        index++;
        args.push(sum());
      }
      expect(")");
      if (args.length !== EXERCISE_FUNCTIONS[name]) throw new Error(`${name}() takes ${EXERCISE_FUNCTIONS[name]} argument(s) ${where(token)}`);
      return name === "sqrt" ? ["^", args[0], ["n", 0.5]] : ["f", name, ...args];
    }
    if (name === "pi") return ["n", Math.PI];
    if (name === "E") return ["n", Math.E];
    if (name in EXERCISE_FUNCTIONS) throw new Error(`'${name}' is a function: write ${name}(...) ${where(token)}`);
    if (!known.has(name)) throw new Error(`unknown symbol '${name}' ${where(token)}`);
    return ["s", name];
  }
  if (peek().kind === "end") throw new Error("empty expression");
  const tree = sum();
  if (peek().kind !== "end") throw new Error(`unexpected '${peek().value ?? peek().kind}' ${where(peek())}`);
  return tree;
}

// -- values -----------------------------------------------------------------------------------
const EXERCISE_CALLS = {
  sin: Math.sin, cos: Math.cos, tan: Math.tan, cot: (x) => 1 / Math.tan(x),
  sec: (x) => 1 / Math.cos(x), csc: (x) => 1 / Math.sin(x), asin: Math.asin, acos: Math.acos,
  atan: Math.atan, atan2: Math.atan2, sinh: Math.sinh, cosh: Math.cosh, tanh: Math.tanh,
  exp: Math.exp, log: Math.log, Abs: Math.abs, sign: Math.sign,
};

function exerciseValue(tree, env) {
  switch (tree[0]) {
    case "n": return tree[1];
    case "s": return env[tree[1]];
    case "+": return tree.slice(1).reduce((total, t) => total + exerciseValue(t, env), 0);
    case "*": return tree.slice(1).reduce((total, t) => total * exerciseValue(t, env), 1);
    case "^": return Math.pow(exerciseValue(tree[1], env), exerciseValue(tree[2], env));
    case "f": return EXERCISE_CALLS[tree[1]](...tree.slice(2).map((t) => exerciseValue(t, env)));
  }
  throw new Error(`not an expression tree: ${tree[0]}`);
}

function exerciseSymbols(tree, found = new Set()) {
  if (tree[0] === "s") found.add(tree[1]);
  else if (tree[0] !== "n") for (const t of tree.slice(tree[0] === "f" ? 2 : 1)) exerciseSymbols(t, found);
  return found;
}

// d tree / d name, pruned of zeros (the trees stay small for the second derivatives of L)
function exerciseDiff(tree, name) {
  const zero = ["n", 0];
  const isZero = (t) => t[0] === "n" && t[1] === 0;
  const sum = (parts) => {
    const kept = parts.filter((t) => !isZero(t));
    return kept.length === 0 ? zero : kept.length === 1 ? kept[0] : ["+", ...kept];
  };
  const times = (...factors) => (factors.some(isZero) ? zero : ["*", ...factors]);
  if (!exerciseSymbols(tree).has(name)) return zero;
  switch (tree[0]) {
    case "s": return ["n", 1];
    case "+": return sum(tree.slice(1).map((t) => exerciseDiff(t, name)));
    case "*": {
      const factors = tree.slice(1);
      return sum(factors.map((f, i) => times(...factors.slice(0, i), exerciseDiff(f, name), ...factors.slice(i + 1))));
    }
    case "^": {
      const [, base, exponent] = tree;
      const db = exerciseDiff(base, name);
      const de = exerciseDiff(exponent, name);
      return sum([
        times(exponent, ["^", base, ["+", exponent, ["n", -1]]], db),
        times(tree, ["f", "log", base], de),
      ]);
    }
    case "f": {
      const [, fn, x, y] = tree;
      const dx = exerciseDiff(x, name);
      const inverse = (t) => ["^", t, ["n", -1]];
      const outer = {
        sin: ["f", "cos", x], cos: ["*", ["n", -1], ["f", "sin", x]],
        tan: ["+", ["n", 1], ["^", ["f", "tan", x], ["n", 2]]],
        cot: ["*", ["n", -1], ["+", ["n", 1], ["^", ["f", "cot", x], ["n", 2]]]],
        sec: ["*", ["f", "sec", x], ["f", "tan", x]],
        csc: ["*", ["n", -1], ["f", "csc", x], ["f", "cot", x]],
        asin: ["^", ["+", ["n", 1], ["*", ["n", -1], ["^", x, ["n", 2]]]], ["n", -0.5]],
        acos: ["*", ["n", -1], ["^", ["+", ["n", 1], ["*", ["n", -1], ["^", x, ["n", 2]]]], ["n", -0.5]]],
        atan: inverse(["+", ["n", 1], ["^", x, ["n", 2]]]),
        sinh: ["f", "cosh", x], cosh: ["f", "sinh", x],
        tanh: ["+", ["n", 1], ["*", ["n", -1], ["^", ["f", "tanh", x], ["n", 2]]]],
        exp: tree, log: inverse(x), Abs: ["f", "sign", x], sign: ["n", 0],
      };
      if (fn === "atan2") { // d atan2(x, y) = (y dx - x dy) / (x^2 + y^2)
        const dy = exerciseDiff(y, name);
        return times(sum([times(y, dx), times(["n", -1], x, dy)]), inverse(["+", ["^", x, ["n", 2]], ["^", y, ["n", 2]]]));
      }
      return times(outer[fn], dx);
    }
  }
  return zero;
}

// -- the term-by-term split (lagrangian.analysis.check.terms.split) ------------------------------
// Products multiplied out, integer powers of sums expanded; function calls, other powers of
// sums and non-integer powers kept whole.  A term: {c: number, factors: [[tree, exponent]]}.
function exerciseExpand(tree) {
  const atom = () => [{ c: 1, factors: [[tree, 1]] }];
  const multiply = (left, right) => {
    const out = [];
    for (const a of left) for (const b of right) out.push({ c: a.c * b.c, factors: a.factors.concat(b.factors) });
    return exerciseCollect(out);
  };
  switch (tree[0]) {
    case "n": return [{ c: tree[1], factors: [] }];
    case "s": case "f": return atom();
    case "+": return exerciseCollect(tree.slice(1).flatMap(exerciseExpand));
    case "*": return tree.slice(1).reduce((acc, t) => multiply(acc, exerciseExpand(t)), [{ c: 1, factors: [] }]);
    case "^": {
      const [, base, exponent] = tree;
      if (exponent[0] !== "n" || !Number.isInteger(exponent[1])) return atom();
      const k = exponent[1];
      const inner = exerciseExpand(base);
      if (inner.length === 1) {
        const [t] = inner;
        return [{ c: Math.pow(t.c, k), factors: t.factors.map(([f, e]) => [f, e * k]) }];
      }
      if (k < 1 || k > EXERCISE_MAX_POWER) return atom();
      let out = inner;
      for (let i = 1; i < k; i++) out = multiply(out, inner);
      return out;
    }
  }
  throw new Error(`not an expression tree: ${tree[0]}`);
}

// a number as a short fraction where it is one (SymPy's nsimplify, as check prints a factor)
function exerciseNumber(x) {
  for (let q = 1; q <= 1000; q++) {
    const p = Math.round(x * q);
    if (Math.abs(x - p / q) <= 1e-9 * Math.max(1, Math.abs(x))) return q === 1 ? `${p}` : `${p}/${q}`;
  }
  return `${x}`;
}

// a term as the student reads it: coefficient, then the factors, powers with ^
function exercisePrinted(c, factors) {
  const show = (tree, inside = false) => {
    switch (tree[0]) {
      case "n": return exerciseNumber(tree[1]);
      case "s": return tree[1];
      case "f": return `${tree[1]}(${tree.slice(2).map((t) => show(t)).join(", ")})`;
      case "^": return `${show(tree[1], true)}^${show(tree[2], true)}`;
      case "*": { const text = tree.slice(1).map((t) => show(t, true)).join("*"); return inside ? `(${text})` : text; }
      case "+": { const text = tree.slice(1).map((t) => show(t)).join(" + ").replace(/\+ -/g, "- "); return inside ? `(${text})` : text; }
    }
    return "?";
  };
  const power = ([f, e]) => (e === 1 ? show(f, true) : `${show(f, true)}^${e < 0 || !Number.isInteger(e) ? `(${exerciseNumber(e)})` : e}`);
  const top = factors.filter(([, e]) => e > 0).map(power);
  const bottom = factors.filter(([, e]) => e < 0).map(([f, e]) => power([f, -e]));
  let number = exerciseNumber(Math.abs(c));
  let denominator = "";
  if (number.includes("/")) [number, denominator] = number.split("/");
  const numerator = [number === "1" && top.length ? null : number, ...top].filter(Boolean).join("*");
  const under = [denominator, ...bottom].filter(Boolean);
  const text = under.length ? `${numerator}/${under.length > 1 ? `(${under.join("*")})` : under[0]}` : numerator;
  return (c < 0 ? "-" : "") + text;
}

// like terms added (as SymPy's expand does), each term's equal factors combined; refused past
// EXERCISE_MAX_TERMS terms
function exerciseCollect(terms) {
  const found = new Map();
  for (const term of terms) {
    const merged = new Map();
    for (const [f, e] of term.factors) {
      const key = JSON.stringify(f);
      merged.set(key, [f, (merged.get(key)?.[1] ?? 0) + e]);
    }
    const keys = [...merged.keys()].filter((k) => merged.get(k)[1] !== 0).sort();
    const key = keys.map((k) => `${k}^${merged.get(k)[1]}`).join("*");
    const entry = found.get(key);
    if (entry) entry.c += term.c;
    else found.set(key, { c: term.c, factors: keys.map((k) => merged.get(k)) });
  }
  const out = [...found.values()].filter((t) => t.c !== 0);
  if (out.length > EXERCISE_MAX_TERMS) throw new Error(`too many terms to compare one by one (more than ${EXERCISE_MAX_TERMS} once multiplied out)`);
  return out;
}
