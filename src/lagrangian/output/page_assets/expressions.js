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

// lagrangian/parsing/parser.py's grammar on the tokens of tokens.js; in LaTeX a factor
// written after another multiplies, "^" takes one signed primary, \frac, \sqrt[n]{x} and
// \sin^2\theta are read, and a name before a group is a product whose group alone takes a
// power: k (r - l)^2 is k*(r - l)^2 (builder.py, commit c226dad)
function exerciseParse(text, known) {
  const latex = text.includes("\\") || text.includes("{");
  const tokens = exerciseTokens(text, latex);
  let index = 0;
  const peek = () => tokens[index];
  const next = () => (tokens[index].kind === "end" ? tokens[index] : tokens[index++]);
  const where = (token) => `at position ${token.at + 1}`;
  const shown = (token) => (token.kind === "end" ? "end of expression" : `'${token.text}'`);
  const closers = { "(": ")", "[": "]", "{": "}" };
  const starts = new Set(["number", "name", "function", "(", "[", "{", "frac", "sqrt"]);
  const expectClose = (opening) => {
    const token = peek();
    if (token.kind !== closers[opening.kind]) {
      throw new Error(`expected '${closers[opening.kind]}' to close '${opening.text}' at position ${opening.at + 1}, found ${shown(token)} ${where(token)}`);
    }
    next();
  };
  const unexpected = (token) => new Error(`unexpected ${token.kind === "end" ? "end of expression" : shown(token)} ${where(token)}`);
  // a LaTeX name before a one-argument group: ["j", name, group] until power() or settle()
  const settle = (tree) => (tree[0] === "j" ? ["*", tree[1], tree[2]] : tree);
  const negate = (tree) => ["*", ["n", -1], tree];
  // names are resolved once the whole text is read, as builder.py does after the parser: a
  // text with a syntax error is refused for that first
  let unresolved = null;
  const unresolve = (message, token) => {
    unresolved ??= new Error(`${message} ${where(token)}`);
    return ["n", NaN];
  };
  function sum() {
    const terms = [term()];
    while (peek().kind === "+" || peek().kind === "-") {
      const negative = next().kind === "-";
      const t = term();
      terms.push(negative ? negate(t) : t);
    }
    return terms.length === 1 ? terms[0] : ["+", ...terms];
  }
  function term() {
    const factors = [unary()];
    for (;;) {
      const token = peek();
      if (token.kind === "*" || token.kind === "/") {
        next();
        const factor = unary();
        factors.push(token.kind === "/" ? ["^", factor, ["n", -1]] : factor);
      } else if (starts.has(token.kind)) {
        const previous = tokens[index - 1];
        if (!latex) {
          if (previous.kind === "number" && token.kind === "(") throw new Error(`'${previous.text}' is not a function: write '${previous.text}*(...)' to multiply ${where(previous)}`);
          throw new Error(`implicit multiplication is not allowed: write '${previous.text}*${token.text}' ${where(token)}`);
        }
        if (token.kind === "number") throw new Error(`write '\\cdot' before the number ${shown(token)}, or put the number first ${where(token)}`);
        factors.push(power());
      } else break;
    }
    return factors.length === 1 ? factors[0] : ["*", ...factors];
  }
  function unary() {
    const token = peek();
    if (token.kind !== "+" && token.kind !== "-") return power();
    next();
    const operand = unary();
    return token.kind === "-" ? negate(operand) : operand;
  }
  function power() {
    const base = primary();
    const caret = peek();
    if (caret.kind !== "^") return settle(base);
    next();
    const exponent = latex ? signedPrimary() : unary();
    if (latex && peek().kind === "^") throw new Error(`double superscript: use braces, as in x^{a^b} ${where(peek())}`);
    return base[0] === "j" ? ["*", base[1], ["^", base[2], exponent]] : ["^", base, exponent];
  }
  // a LaTeX superscript: x^2, x^{a+b}, x^-1
  function signedPrimary() {
    const sign = peek();
    if (sign.kind !== "+" && sign.kind !== "-") return settle(primary());
    next();
    const operand = settle(primary());
    return sign.kind === "-" ? negate(operand) : operand;
  }
  function group() {
    const opening = next();
    const inside = sum();
    expectClose(opening);
    return inside;
  }
  function primary() {
    const token = peek();
    if (token.kind === "number") { next(); return ["n", token.value]; }
    if (token.kind === "name") { next(); return name(token); }
    if (token.kind in closers && (latex || token.kind === "(")) return group();
    if (token.kind === "frac") return fraction();
    if (token.kind === "sqrt") return root();
    if (token.kind === "function") return command();
    throw unexpected(token);
  }
  function call(name, args, token) {
    if (args.length !== EXERCISE_FUNCTIONS[name]) {
      const n = EXERCISE_FUNCTIONS[name];
      throw new Error(`${name}() takes ${n} argument${n === 1 ? "" : "s"} (${args.length} given) ${where(token)}`);
    }
    return name === "sqrt" ? ["^", args[0], ["n", 0.5]] : ["f", name, ...args];
  }
  function name(token) {
    const name = token.value;
    if (peek().kind === "(") {
      const args = callArguments(next());
      if (name in EXERCISE_FUNCTIONS) return call(name, args, token);
      if (latex && args.length === 1) return ["j", symbol(token), args[0]]; // LaTeX m(a + b)
      if (known.has(name)) return unresolve(`'${name}' is not a function`, token);
      const meant = tokenLikelyMeant(name, Object.keys(EXERCISE_FUNCTIONS));
      return unresolve(`unknown function '${name}'${meant ? ` (did you mean '${meant}'?)` : ""}`, token);
    }
    if (name in EXERCISE_FUNCTIONS) throw new Error(`'${name}' is a function: write ${name}(...) ${where(token)}`);
    return symbol(token);
  }
  function symbol(token) {
    if (token.value === "pi") return ["n", Math.PI];
    if (token.value === "E") return ["n", Math.E];
    if (known.has(token.value)) return ["s", token.value];
    const meant = tokenLikelyMeant(token.value, known);
    return unresolve(`unknown symbol '${token.value}'${meant ? ` (did you mean '${meant}'?)` : ""}`, token);
  }
  function callArguments(opening) {
    const args = [];
    if (peek().kind !== ")") {
      args.push(sum());
      while (peek().kind === ",") { next(); args.push(sum()); }
    }
    expectClose(opening);
    return args;
  }
  // the argument of \frac or \sqrt: a braced group or one primary (never a number of two digits)
  function argument(command) {
    const token = peek();
    if (token.kind === "{") return group();
    if (token.kind === "number" && token.text.length > 1) throw new Error(`ambiguous argument ${shown(token)} of '${command.text}': use braces, as in \\frac{1}{2} ${where(token)}`);
    return settle(primary());
  }
  function fraction() {
    const command = next();
    const numerator = argument(command);
    return ["*", numerator, ["^", argument(command), ["n", -1]]];
  }
  function root() {
    const command = next();
    let degree = null;
    if (peek().kind === "[") {
      const opening = next();
      degree = sum();
      expectClose(opening);
    }
    const radicand = argument(command);
    return degree === null ? ["^", radicand, ["n", 0.5]] : ["^", radicand, ["^", degree, ["n", -1]]];
  }
  // \sin x, \sin(x), \sin^2 x (sin(x)^2), \sin x^2 (sin(x^2))
  function command() {
    const token = next();
    let exponent = null, caret = null;
    if (peek().kind === "^") {
      caret = next();
      exponent = signedPrimary();
      const negated = exponent[0] === "*" && exponent.length === 3 && exponent[1][0] === "n" && exponent[1][1] === -1; // only negate() makes a literal -1
      if (negated) throw new Error(`'${token.text}^{-1}' is ambiguous: write the inverse function or (${token.text} x)^{-1} ${where(caret)}`);
    }
    let args;
    if (peek().kind === "(") args = callArguments(next());
    else {
      const first = peek();
      const operand = unary();
      if (operand[0] === "n" && first.kind === "number" && starts.has(peek().kind)) {
        throw new Error(`ambiguous argument of '${token.text}': use parentheses, as in ${token.text}(${first.text} x) ${where(first)}`);
      }
      args = [operand];
    }
    const tree = call(token.value, args, token);
    return exponent === null ? tree : ["^", tree, exponent];
  }
  if (peek().kind === "end") throw new Error("empty expression at position 1");
  const tree = sum();
  const left = peek();
  if (left.kind === ")" || left.kind === "]" || left.kind === "}") throw new Error(`unmatched ${shown(left)} ${where(left)}`);
  if (left.kind !== "end") throw unexpected(left);
  if (unresolved) throw unresolved;
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
