// The equilibria and normal modes of a page (lagrangian page), in view and as numbers.
//
// Each equilibrium of the document (lagrangian/output/page_results.py) becomes one block:
// the point and its verdict first, a table of omega^2, omega, the period and the shape of
// every mode at the parameter values of the moment, then the symbolic forms, typeset in
// KaTeX's inline mode so that they break across lines.  The numbers come from the
// generated routine results(t, y, params) (its column X; an entry of the document is
// {x: index}, {number: value} or null); update(params) refreshes them when a slider moves.
//
// fit(root) shrinks a formula that is still wider than its column (a fraction or a root
// is one box KaTeX cannot break) until it fits: nothing of the analysis overflows.
function lagrangianResults(evaluate, element, typesetMath) {
  "use strict";
  const blocks = [];
  const SMALLEST = 0.45; // the least font scale a formula is shrunk to

  const format = (x) => (Number.isFinite(x) ? String(Number(x.toPrecision(6))) : "\u2014");

  // one number of the document at `values` (the column X now): NaN where it is not real
  // or cannot be evaluated here
  function valueOf(entry, values) {
    if (!entry) return NaN;
    if ("number" in entry) return entry.number;
    return values ? values[entry.x] : NaN;
  }

  function block(spec) {
    const box = element("div", { class: "equilibrium" });
    const head = element("div", { class: "equilibrium-head" });
    const point = element("span", { class: "point" });
    typesetMath(spec.point.map((p) => p.latex).join(",\\ ") || "\\text{every configuration}", point, false);
    const verdict = element("span", { class: "verdict" });
    head.append(point, verdict);
    const located = element("div", { class: "located" });
    const table = element("table", { class: "modes" });
    const header = element("tr");
    for (const name of ["#", "\u03c9\u00b2", "\u03c9", "period", "shape"]) header.append(element("th", {}, name));
    const body = element("tbody");
    table.append(element("thead"), body);
    table.firstChild.append(header);
    const rows = spec.modes.map((mode, k) => {
      const row = element("tr");
      const cells = [0, 1, 2, 3, 4].map(() => element("td"));
      cells[0].textContent = String(k + 1);
      row.append(...cells);
      body.append(row);
      return cells;
    });
    box.append(head, located);
    if (spec.modes.length) box.append(element("div", { class: "table" }));
    if (spec.modes.length) box.lastChild.append(table);
    spec.modes.forEach((mode, k) => {
      const math = element("div", { class: "math wrap" });
      typesetMath(`\\omega_{${k + 1}}^2 = ${mode.latex}`, math, false);
      box.append(math);
    });
    const condition = element("div", { class: "math wrap" });
    if (spec.condition) {
      typesetMath(`\\text{stable iff }${spec.condition}`, condition, false);
      box.append(condition);
    }
    for (const remark of spec.remarks) box.append(element("p", {}, remark));
    blocks.push({ spec, verdict, located, rows, numbers: [] });
    return box;
  }

  // the verdict from the numbers: a negative omega^2 grows, a zero one is neutral
  function judged(squares) {
    if (!squares.length || !squares.every(Number.isFinite)) return null;
    const scale = Math.max(...squares.map(Math.abs));
    const tolerance = 1e-9 * (scale || 1);
    if (squares.some((s) => s < -tolerance)) return "unstable";
    if (squares.some((s) => Math.abs(s) <= tolerance)) return "marginal";
    return "stable";
  }

  function update(params) {
    let values = null;
    if (evaluate) {
      try {
        values = evaluate(0, [], params).flat(2);
      } catch (error) {
        values = null;
      }
    }
    for (const entry of blocks) {
      const { spec, verdict, located, rows } = entry;
      const where = spec.point.map((p) => valueOf(p.value, values));
      const exists = where.every(Number.isFinite);
      const squares = spec.modes.map((mode) => valueOf(mode.value, values));
      const byNumbers = spec.judged && exists ? judged(squares) : null;
      let text = spec.stability;
      if (!exists) text = "not an equilibrium at these values (no real solution)";
      else if (spec.depends && byNumbers) text = `${byNumbers} at these values`;
      else if (spec.depends) text = `${spec.stability} at the values the page was written with`;
      verdict.textContent = text;
      verdict.dataset.verdict = exists ? byNumbers || spec.stability : "none";
      entry.numbers = squares;
      const moving = spec.point.filter((p) => p.value && "x" in p.value);
      located.textContent = moving.length && exists ? `at ${spec.point.map((p, i) => `${p.name} = ${format(where[i])}`).join(", ")}` : "";
      squares.forEach((s, k) => {
        const cells = rows[k];
        cells[1].textContent = format(s);
        if (s > 0) {
          const omega = Math.sqrt(s);
          cells[2].textContent = format(omega);
          cells[3].textContent = format((2 * Math.PI) / omega);
        } else if (s < 0) {
          // no oscillation: a departure grows as exp(lambda t)
          cells[2].textContent = `\u03bb = ${format(Math.sqrt(-s))}`;
          cells[2].title = "omega^2 < 0: a small departure grows as exp(lambda t)";
          cells[3].textContent = "\u2014";
        } else {
          cells[2].textContent = "\u2014";
          cells[3].textContent = "\u2014";
        }
        const shape = spec.modes[k].shape.map((entry) => valueOf(entry, values));
        cells[4].textContent = shape.length ? `(${shape.map(format).join(", ")})` : "";
      });
    }
  }

  function fit(root) {
    // the analysis' formulas only: the other long formulas of the solution scroll sideways
    for (const box of root.querySelectorAll(".math.wrap")) {
      box.style.fontSize = "";
      let scale = 1;
      // a few rounds: the parts of KaTeX's boxes set in pixels do not shrink with the font
      for (let round = 0; round < 6 && box.clientWidth > 0 && box.scrollWidth > box.clientWidth && scale > SMALLEST; round++) {
        scale = Math.max(SMALLEST, (scale * box.clientWidth) / box.scrollWidth - 0.01);
        box.style.fontSize = `${(scale * 100).toFixed(1)}%`;
      }
    }
  }

  // for the hook: each equilibrium's verdict now and its omega^2 (NaN: not evaluated)
  const now = () => blocks.map((b) => ({ verdict: b.verdict.dataset.verdict, omega_squared: b.numbers.slice() }));
  return { block, update, fit, now };
}
