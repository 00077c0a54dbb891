// The exercise of a model's page (lagrangian page MODEL --exercise): the student types T, V,
// L and the equations; check.js checks each answer here, offline, as `lagrangian check` does.

// -- the page's exercise panel ------------------------------------------------------------------
// Above the worked solution, which stays hidden until every answer asked is right (or the
// student asks for it): one field per step, a Check button, the verdict with the terms at
// fault, and the step's answer on request.  `window.lagrangianCheck(step, text)` is the same
// checker for tests and for a course page's own scripts.
const EXERCISE_TITLES = {
  kinetic: ["Kinetic energy", "T ="],
  potential: ["Potential energy", "V ="],
  lagrangian: ["Lagrangian", "L ="],
};

function lagrangianExercise(data, solution) {
  const make = (tag, attributes = {}, text = null) => {
    const node = document.createElement(tag);
    for (const [k, v] of Object.entries(attributes)) node.setAttribute(k, v);
    if (text !== null) node.textContent = text;
    return node;
  };
  const math = (latex, node) => {
    if (window.katex) window.katex.render(latex, node, { throwOnError: false, strict: "ignore", trust: false });
    else node.textContent = latex;
  };
  const panel = make("section", { class: "exercise", id: "exercise", "aria-label": "exercise" });
  panel.append(make("h2", {}, "Exercise"));
  for (const note of data.notes) panel.append(make("p", { class: "exercise-note" }, note));
  solution.prepend(panel);
  if (!data.steps.length) return; // nothing asked: the worked solution stays in view
  const checker = exerciseChecker(data);
  const worked = [...solution.children].filter((node) => node !== panel);
  for (const node of worked) node.hidden = true;
  const names = [...data.names.coordinates.flatMap((c) => [c.name, c.velocity, c.acceleration]), ...data.names.parameters.map((p) => p.name)];
  panel.append(make("p", {}, "Derive each step yourself; each answer is checked in this page, offline. "
    + `Write as in a model file (m*l^2*theta_dot^2/2, cos(theta)) with the names ${names.join(", ")}; `
    + "an equation as lhs = rhs or as an expression equal to 0."));
  const rows = [];

  function row(step, title, index = null) {
    const id = index === null ? `exercise-${step}` : `exercise-${step}-${index}`;
    const box = make("div", { class: "exercise-step", "data-step": step });
    const label = make("label", { for: id }, `${title} `);
    const input = make("input", { id, type: "text", spellcheck: "false", autocomplete: "off", "aria-label": title });
    const check = make("button", { type: "button", class: "exercise-check" }, "Check");
    const show = make("button", { type: "button", class: "exercise-show" }, "Show the answer");
    const verdict = make("div", { class: "exercise-verdict", role: "status" });
    const answer = make("div", { class: "exercise-answer", hidden: "" });
    const entry = { step, verdict: null };
    check.addEventListener("click", () => {
      const result = checker.check(step, input.value);
      entry.verdict = result.verdict;
      verdict.className = `exercise-verdict exercise-${result.verdict}`;
      verdict.dataset.verdict = result.verdict;
      const word = { right: "Right", equivalent: "Right, equivalently", wrong: "Wrong", error: "Cannot read this" }[result.verdict];
      verdict.textContent = "";
      verdict.append(make("strong", {}, `${word}: `), document.createTextNode(result.reason));
      if (rows.every((r) => r.verdict === "right" || r.verdict === "equivalent")) reveal();
    });
    input.addEventListener("keydown", (event) => { if (event.key === "Enter") check.click(); });
    show.addEventListener("click", () => {
      const right = index === null ? data[step] : data.equations[index];
      answer.hidden = false;
      math(index === null ? `${title.replace("=", "").trim()} = ${right.latex}` : `${right.latex} = 0`, answer);
    });
    box.append(label, input, check, show, verdict, answer);
    panel.append(box);
    rows.push(entry);
  }

  for (const step of data.steps) {
    if (step === "equations") {
      data.names.coordinates.forEach((c, i) => row("equations", `Equation of motion ${i + 1} (of ${c.name}):`, i));
    } else {
      row(step, EXERCISE_TITLES[step][1]);
    }
  }
  const revealButton = make("button", { type: "button", class: "exercise-reveal" }, "Show the worked solution");
  function reveal() {
    for (const node of worked) node.hidden = false;
    revealButton.hidden = true;
  }
  revealButton.addEventListener("click", reveal);
  panel.append(revealButton);
  window.lagrangianCheck = (step, text) => checker.check(step, text);
}
