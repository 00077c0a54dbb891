// The page's share link and embed mode (lagrangian page).
//
// A link is the page's own address with a fragment that holds what makes a run:
//   #p.g=9.81&p.m1=1&q.theta1=2&q.theta1_dot=0&method=dop853&t=7.25
// p.NAME a parameter or input, q.NAME an initial coordinate or velocity, method the
// integrator, t the time shown; every number written as JavaScript's shortest text that
// reads back as the same double, so the values are exact.  The page that opens it runs
// from t = 0 to t in one call, as the page that shared it did when its link was made:
// both step through the same steps and show the same state to the last digit.
//
// "embed" in the fragment (#embed, or #embed&p.g=...) shows the animation and its
// controls only, for an <iframe sandbox="allow-scripts"> in a course page or slides.
// Nothing here touches storage, cookies or the history: a sandboxed frame has none.
function lagrangianShare() {
  "use strict";
  const exact = (x) => String(x); // the shortest round-trip text of a double

  // the fragment of a run: {parameters: {name: value}, initial: {...}, method, t}
  function fragment(run, embed = false) {
    const parts = embed ? ["embed"] : [];
    for (const [name, value] of Object.entries(run.parameters)) parts.push(`p.${encodeURIComponent(name)}=${exact(value)}`);
    for (const [name, value] of Object.entries(run.initial)) parts.push(`q.${encodeURIComponent(name)}=${exact(value)}`);
    parts.push(`method=${encodeURIComponent(run.method)}`, `t=${exact(run.t)}`);
    return parts.join("&");
  }

  // what a fragment asks for; `problems` names each part that could not be read
  function read(hash) {
    const asked = { parameters: {}, initial: {}, method: null, t: null, embed: false, problems: [] };
    const text = hash.startsWith("#") ? hash.slice(1) : hash;
    if (!text) return asked;
    for (const part of text.split("&")) {
      if (!part) continue;
      if (part === "embed") {
        asked.embed = true;
        continue;
      }
      const equals = part.indexOf("=");
      let key;
      let value;
      try {
        key = decodeURIComponent(equals < 0 ? part : part.slice(0, equals));
        value = equals < 0 ? "" : decodeURIComponent(part.slice(equals + 1));
      } catch (error) {
        asked.problems.push(`'${part}' is not readable`);
        continue;
      }
      if (key === "method") {
        asked.method = value;
        continue;
      }
      const number = value.trim() === "" ? NaN : Number(value);
      if (!Number.isFinite(number)) {
        asked.problems.push(`${key}: not a finite number: '${value}'`);
      } else if (key === "t") {
        asked.t = number;
      } else if (key.startsWith("p.")) {
        asked.parameters[key.slice(2)] = number;
      } else if (key.startsWith("q.")) {
        asked.initial[key.slice(2)] = number;
      } else {
        asked.problems.push(`'${key}' is not part of a link of this page`);
      }
    }
    return asked;
  }

  // the address of the page without its fragment (about:srcdoc in a frame made from text)
  const base = () => window.location.href.split("#")[0];

  return { fragment, read, link: (run) => `${base()}#${fragment(run)}` };
}
