// The tokens of a student's answer on the exercise page, plain text or LaTeX, by the rules of
// the project's parser (lagrangian/parsing: lexer.py for plain text and Unicode, latex.py for
// LaTeX), so that the page reads every answer `lagrangian check` reads and reads it the same
// way.  Text is LaTeX where it holds a backslash or a brace (latex.looks_like_latex).
// A token: {kind, at, value, text}; kinds "number", "name", "function" (a LaTeX function
// command), "frac", "sqrt", "^" "+" "-" "*" "/" ( ) [ ] { } "," and "end".

const TOKEN_WHITESPACE = " \t\r\n\f\v\u00a0";
const TOKEN_GREEK_NAMES = [
  "alpha", "beta", "gamma", "delta", "epsilon", "zeta", "eta", "theta", "iota", "kappa", "lambda",
  "mu", "nu", "xi", "omicron", "pi", "rho", "sigma", "tau", "upsilon", "phi", "chi", "psi", "omega",
];
const TOKEN_UPPER_GREEK = ["Gamma", "Delta", "Theta", "Lambda", "Xi", "Pi", "Sigma", "Upsilon", "Phi", "Psi", "Omega"];
// names.UNICODE_GREEK: a Greek character -> its name (variant forms -> the plain name)
const TOKEN_UNICODE_GREEK = {
  ...Object.fromEntries([..."αβγδεζηθικλμνξοπρστυφχψω"].map((c, i) => [c, TOKEN_GREEK_NAMES[i]])),
  ...Object.fromEntries([..."ΓΔΘΛΞΠΣΥΦΨΩ"].map((c, i) => [c, TOKEN_UPPER_GREEK[i]])),
  ς: "sigma", ϑ: "theta", ϕ: "phi", ϵ: "epsilon", ϱ: "rho", µ: "mu",
};
// names.LATEX_GREEK: a command without its backslash -> the name
const TOKEN_LATEX_GREEK = {
  ...Object.fromEntries([...TOKEN_GREEK_NAMES, ...TOKEN_UPPER_GREEK].map((n) => [n, n])),
  ...Object.fromEntries(["varepsilon", "vartheta", "varkappa", "varpi", "varrho", "varsigma", "varphi"].map((n) => [n, n])),
  ell: "l",
};
// names.LATEX_FUNCTIONS
const TOKEN_LATEX_FUNCTIONS = {
  sin: "sin", cos: "cos", tan: "tan", cot: "cot", sec: "sec", csc: "csc", arcsin: "asin",
  arccos: "acos", arctan: "atan", sinh: "sinh", cosh: "cosh", tanh: "tanh", exp: "exp", ln: "log", log: "log",
};
const TOKEN_UNICODE_OPERATORS = { "·": "*", "×": "*", "⋅": "*", "−": "-", "÷": "/" };
const TOKEN_SUPERSCRIPTS = "⁰¹²³⁴⁵⁶⁷⁸⁹";
const TOKEN_SUBSCRIPTS = "₀₁₂₃₄₅₆₇₈₉";
const TOKEN_DOTS = { "\u0307": 1, "\u0308": 2 }; // combining dot above, diaeresis
const TOKEN_SPACING = new Set([",", ";", ":", "!", " ", "quad", "qquad", "displaystyle", "textstyle"]);
const TOKEN_COMMAND_OPERATORS = { cdot: "*", times: "*", div: "/" };
const TOKEN_ACCENTS = { dot: 1, ddot: 2 };

const tokenAscii = (c) => c !== undefined && /^[A-Za-z]$/.test(c);
const tokenDigit = (c) => c !== undefined && c >= "0" && c <= "9";
// Python's str.isprintable and lexer.describe_char
const tokenPrintable = (c) => c === " " || !/[\p{C}\p{Z}]/u.test(c);
const tokenShown = (c) => (c === "'" ? "\"'\"" : tokenPrintable(c) && !/\s/u.test(c) ? `'${c}'` : `U+${c.codePointAt(0).toString(16).toUpperCase().padStart(4, "0")}`);

function tokenError(message, at) {
  return new Error(`${message} at position ${at + 1}`);
}

// a precomposed letter as [base letter, dots above it]: ẋ -> ["x", 1] (lexer._decompose)
function tokenDecompose(c) {
  if (c.charCodeAt(0) < 128) return [c, 0];
  const parts = [...c.normalize("NFD")];
  if (parts.length < 2 || parts.slice(1).some((m) => !(m in TOKEN_DOTS))) return [c, 0];
  return [parts[0], parts.slice(1).reduce((n, m) => n + TOKEN_DOTS[m], 0)];
}

const tokenLetter = (c) => tokenAscii(c) || c in TOKEN_UNICODE_GREEK;

function tokenStartsName(text, i) {
  if (tokenLetter(text[i])) return true;
  const [base, dots] = tokenDecompose(text[i]);
  return dots > 0 && tokenLetter(base);
}

function tokenWithDots(name, dots, at) {
  if (dots === 0) return name;
  if (dots > 2) throw tokenError(`too many dots over '${name}' (at most 2)`, at);
  return name + (dots === 1 ? "_dot" : "_ddot");
}

function tokenCheckName(name, at) {
  if (name.includes("__")) throw tokenError(`invalid name '${name}': names may not contain '__'`, at);
  return name;
}

// lexer.scan_name: Greek letters spelled out, subscript digits as digits, dots as a suffix
function tokenScanName(text, start, underscores) {
  let name = "";
  let dots = 0;
  let i = start;
  for (; i < text.length; i++) {
    const c = text[i];
    if (tokenAscii(c) || tokenDigit(c) || (underscores && c === "_")) name += c;
    else if (c in TOKEN_UNICODE_GREEK) name += TOKEN_UNICODE_GREEK[c];
    else if (TOKEN_SUBSCRIPTS.includes(c)) name += TOKEN_SUBSCRIPTS.indexOf(c);
    else if (c in TOKEN_DOTS) dots += TOKEN_DOTS[c];
    else {
      const [base, extra] = tokenDecompose(c);
      if (!extra || !tokenLetter(base)) break;
      name += TOKEN_UNICODE_GREEK[base] ?? base;
      dots += extra;
    }
  }
  return [tokenWithDots(name, dots, start), i];
}

const tokenStartsNumber = (text, i) => tokenDigit(text[i]) || (text[i] === "." && tokenDigit(text[i + 1]));

function tokenScanNumber(text, start) {
  const found = /\d*(?:\.\d*)?/y;
  found.lastIndex = start;
  let end = start + found.exec(text)[0].length;
  const exponent = /[eE][+-]?\d+/y;
  exponent.lastIndex = end;
  const more = exponent.exec(text);
  if (more) end += more[0].length;
  return [Number(text.slice(start, end)), end];
}

// the operator at i (** and ^ both "^", x² as ^ 2, x⁻¹ as ^ - 1), or null where there is none
function tokenOperator(text, i, push) {
  const c = text[i];
  if (text.startsWith("**", i)) { push("^", i, i + 2); return i + 2; }
  if ("+-*/^".includes(c)) { push(c, i, i + 1); return i + 1; }
  if (c in TOKEN_UNICODE_OPERATORS) { push(TOKEN_UNICODE_OPERATORS[c], i, i + 1); return i + 1; }
  if (TOKEN_SUPERSCRIPTS.includes(c) || c === "⁻") {
    push("^", i, i + 1);
    if (c === "⁻") { push("-", i, i + 1); i++; }
    const start = i;
    while (i < text.length && TOKEN_SUPERSCRIPTS.includes(text[i])) i++;
    if (i === start) throw tokenError("expected superscript digits", i);
    push("number", start, i, Number([...text.slice(start, i)].map((d) => TOKEN_SUPERSCRIPTS.indexOf(d)).join("")));
    return i;
  }
  return null;
}

function exerciseTokens(text, latex) {
  const tokens = [];
  const push = (kind, start, end, value) => tokens.push({ kind, at: start, value, text: text.slice(start, end) });
  const skipSpace = (i) => { while (i < text.length && TOKEN_WHITESPACE.includes(text[i])) i++; return i; };
  const punctuation = latex ? "()[]{}," : "(),";

  // latex._Scanner.command_name: the command at the backslash `start`, and the offset after it
  function commandName(start) {
    let i = start + 1;
    if (i >= text.length) throw tokenError("expected a command after '\\'", start);
    if (!tokenAscii(text[i])) {
      if (!tokenPrintable(text[i])) throw tokenError(`unexpected character ${tokenShown(text[i])}`, i);
      return [text[i], i + 1];
    }
    while (i < text.length && tokenAscii(text[i])) i++;
    return [text.slice(start + 1, i), i];
  }

  function subscriptPart(i) {
    if (text[i] === "\\") {
      const [name, end] = commandName(i);
      if (!(name in TOKEN_LATEX_GREEK)) throw tokenError(`unexpected '\\${name}' in a subscript`, i);
      return [TOKEN_LATEX_GREEK[name], end];
    }
    let end = i;
    while (end < text.length && (tokenAscii(text[end]) || tokenDigit(text[end]))) end++;
    if (end === i) throw tokenError(`unexpected ${tokenShown(text[i])} in a subscript`, i);
    return [text.slice(i, end), end];
  }

  function subscript(i, underscore) {
    if (text[i] === "{") {
      const parts = [];
      i = skipSpace(i + 1);
      while (i < text.length && text[i] !== "}") {
        const [part, end] = subscriptPart(i);
        parts.push(part);
        i = skipSpace(end);
      }
      if (i >= text.length) throw tokenError("expected '}' to close the subscript", i);
      if (!parts.length) throw tokenError("empty subscript", underscore);
      return [parts.join(""), i + 1];
    }
    if (text[i] === "\\" || tokenAscii(text[i]) || tokenDigit(text[i])) return subscriptPart(i);
    throw tokenError("expected a subscript after '_'", underscore);
  }

  // a digit subscript is appended (theta_1 -> theta1), any other with "_" (l_{ab} -> l_ab)
  function subscripts(i, name) {
    while (i < text.length && text[i] === "_") {
      const [content, end] = subscript(skipSpace(i + 1), i);
      name += /^\d+$/.test(content) ? content : `_${content}`;
      i = end;
    }
    return [name, i];
  }

  function accentTarget(i, command, whole) {
    if (text[i] === "\\") {
      const [name, end] = commandName(i);
      if (!(name in TOKEN_LATEX_GREEK)) throw tokenError(`cannot put '\\${command}' over '\\${name}'`, i);
      return [TOKEN_LATEX_GREEK[name], end];
    }
    if (i < text.length && tokenStartsName(text, i)) {
      if (whole) return tokenScanName(text, i, false);
      if (text[i] in TOKEN_UNICODE_GREEK) return [TOKEN_UNICODE_GREEK[text[i]], i + 1];
      if (tokenAscii(text[i])) return [text[i], i + 1];
    }
    throw tokenError(`expected a name after '\\${command}'`, i);
  }

  // \dot{x}, \dot x, \ddot{\theta_1}, \dot{\theta}_1: one name
  function accent(start, i, command) {
    let base;
    i = skipSpace(i);
    if (text[i] === "{") {
      [base, i] = accentTarget(skipSpace(i + 1), command, true);
      [base, i] = subscripts(i, base);
      i = skipSpace(i);
      if (text[i] !== "}") throw tokenError(`expected '}' to close '\\${command}{'`, i);
      i++;
    } else {
      [base, i] = accentTarget(i, command, false);
    }
    [base, i] = subscripts(i, base);
    push("name", start, i, tokenCheckName(tokenWithDots(base, TOKEN_ACCENTS[command], start), start));
    return i;
  }

  function command(start) {
    const [name, i] = commandName(start);
    if (TOKEN_SPACING.has(name)) return i;
    if (name in TOKEN_LATEX_GREEK) {
      const [symbol, end] = subscripts(i, TOKEN_LATEX_GREEK[name]);
      push("name", start, end, symbol);
      return end;
    }
    if (name in TOKEN_LATEX_FUNCTIONS) push("function", start, i, TOKEN_LATEX_FUNCTIONS[name]);
    else if (name === "frac" || name === "dfrac" || name === "tfrac") push("frac", start, i);
    else if (name === "sqrt") push("sqrt", start, i);
    else if (name in TOKEN_COMMAND_OPERATORS) push(TOKEN_COMMAND_OPERATORS[name], start, i);
    else if (name === "left" || name === "right") {
      const at = skipSpace(i);
      if (!"()[]".includes(text[at] ?? "x")) throw tokenError(`expected one of ( ) [ ] after '\\${name}'`, at);
      push(text[at], start, at + 1);
      return at + 1;
    } else if (name in TOKEN_ACCENTS) return accent(start, i, name);
    else throw tokenError(`unknown LaTeX command '\\${name}'`, start);
    return i;
  }

  let i = 0;
  while (i < text.length) {
    const c = text[i];
    if (TOKEN_WHITESPACE.includes(c)) i++;
    else if (latex && c === "\\") i = command(i);
    else if (tokenStartsNumber(text, i)) {
      const [value, end] = tokenScanNumber(text, i);
      push("number", i, end, value);
      i = end;
    } else if (tokenStartsName(text, i)) {
      let [name, end] = tokenScanName(text, i, !latex);
      if (latex) [name, end] = subscripts(end, name);
      push("name", i, end, tokenCheckName(name, i));
      i = end;
    } else if (!latex && c === "_") {
      throw tokenError(`invalid name '${tokenScanName(text, i, true)[0]}': names may not start with '_'`, i);
    } else if (punctuation.includes(c)) {
      push(c, i, i + 1);
      i++;
    } else {
      const end = tokenOperator(text, i, push);
      if (end === null) throw tokenError(`unexpected character ${tokenShown(c)}`, i);
      i = end;
    }
  }
  tokens.push({ kind: "end", at: text.length, text: "" });
  return tokens;
}

// lagrangian/parsing/suggest.likely_meant: the known name a misspelt one most likely means,
// or null: another spelling of a velocity or an acceleration (xdot, dx, thetaddot), or one
// edit away (not of a digit or a letter's case) from a known name of 4 characters or more
const TOKEN_VELOCITY_FORMS = ["{q}dot", "{q}_d", "{q}d", "{q}dott", "{q}_dott", "d{q}", "d_{q}", "{q}dt", "{q}_dt", "d{q}dt", "{q}prime", "{q}_prime"];
const TOKEN_ACCELERATION_FORMS = ["{q}ddot", "{q}_dd", "{q}dd", "{q}ddott", "{q}_ddott", "dd{q}", "dd_{q}", "d2{q}", "{q}_dddot", "{q}dddot"];

function tokenLikelyMeant(name, known) {
  const candidates = [...new Set(known)].filter((n) => n !== name).sort();
  const folded = name.toLowerCase();
  for (const candidate of candidates) {
    for (const [suffix, forms] of [["_dot", TOKEN_VELOCITY_FORMS], ["_ddot", TOKEN_ACCELERATION_FORMS]]) {
      if (!candidate.endsWith(suffix)) continue;
      const base = candidate.slice(0, -suffix.length);
      if (suffix === "_dot" && base.endsWith("_d")) continue; // x_ddot: an acceleration
      if (forms.some((f) => f.replace("{q}", base).toLowerCase() === folded)) return candidate;
    }
  }
  return candidates.find((c) => c.length >= 4 && tokenOneSlipApart(name, c)) ?? null;
}

function tokenOneSlipApart(a, b) {
  if (Math.abs(a.length - b.length) > 1 || a === b) return false;
  let start = 0;
  while (start < Math.min(a.length, b.length) && a[start] === b[start]) start++;
  if (a.length === b.length) {
    if (a.slice(start + 1) === b.slice(start + 1)) { // one replaced character
      const [x, y] = [a[start], b[start]];
      return !((tokenDigit(x) && tokenDigit(y)) || x.toLowerCase() === y.toLowerCase());
    }
    const swapped = a.slice(start, start + 2) === [...b.slice(start, start + 2)].reverse().join("");
    return swapped && a.slice(start + 2) === b.slice(start + 2);
  }
  const [longer, shorter] = a.length > b.length ? [a, b] : [b, a];
  if (longer.slice(start + 1) !== shorter.slice(start)) return false;
  return !tokenDigit(longer[start]); // one inserted character
}
