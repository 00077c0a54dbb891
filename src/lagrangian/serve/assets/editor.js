// The model editor: each edit (debounced) is POSTed to /page; the answer is the model's
// page, shown in the sandboxed frame, or its one-line error, shown beside the editor while
// the last good page stays.  Every text is shown by value or textContent, never as markup.
// The text is kept in the browser's storage at each edit and restored first on loading,
// so that a reload (after the server crashed, or was restarted) gives the user's model
// back, not the first example.
"use strict";

const DEBOUNCE_MS = 400;
const FIRST_EXAMPLE = "double_pendulum";
const STORED_TEXT = "lagrangian.editor.text";

const editor = document.getElementById("model");
const menu = document.getElementById("examples");
const frame = document.getElementById("page");
const statusLine = document.getElementById("status");
const errorLine = document.getElementById("error");
const exerciseBox = document.getElementById("exercise");

let examples = [];
let timer = null;
let latest = 0;        // the number of the newest request: older answers are ignored
let inFlight = null;   // its AbortController
let typed = false;     // whether the user has typed here: the first example then waits

function showError(text) {
  errorLine.textContent = text;
  errorLine.hidden = false;
}

function clearError() {
  errorLine.textContent = "";
  errorLine.hidden = true;
}

async function derive() {
  const number = ++latest;
  if (inFlight) inFlight.abort();
  inFlight = new AbortController();
  const started = performance.now();
  statusLine.textContent = "deriving\u2026";
  let answer;
  try {
    const response = await fetch(exerciseBox.checked ? "/page?exercise=1" : "/page", {
      method: "POST",
      headers: {"Content-Type": "text/plain; charset=utf-8"},
      body: editor.value,
      signal: inFlight.signal,
    });
    answer = await response.json();
  } catch (error) {
    if (number !== latest) return;
    statusLine.textContent = "";
    showError("the server did not answer: " + error.message);
    return;
  }
  if (number !== latest) return;
  const seconds = ((performance.now() - started) / 1000).toFixed(1);
  if (typeof answer.page === "string") {
    frame.srcdoc = answer.page;   // a property, not markup: the page arrives whole
    clearError();
    statusLine.textContent = "derived in " + seconds + " s";
  } else {
    showError(String(answer.error));
    statusLine.textContent = "the page shows the last model that worked";
  }
}

// Storage may be refused (a private window, a full quota, a policy): the editor then
// works as without it.
function storedText() {
  try {
    return window.localStorage.getItem(STORED_TEXT);
  } catch (error) {
    return null;
  }
}

function keepText() {
  try {
    window.localStorage.setItem(STORED_TEXT, editor.value);
  } catch (error) {
    // not kept: a reload shows the first example
  }
}

function scheduleDerive() {
  clearTimeout(timer);
  timer = setTimeout(derive, DEBOUNCE_MS);
}

function chooseExample(name) {
  const example = examples.find((entry) => entry.name === name);
  if (!example) return;
  menu.value = name;
  editor.value = example.text;
  keepText();
  derive();
}

async function loadExamples() {
  const response = await fetch("/examples");
  examples = (await response.json()).examples;
  for (const example of examples) {
    const option = document.createElement("option");
    option.value = example.name;
    option.textContent = example.title + " (" + example.name + ")";
    menu.appendChild(option);
  }
}

editor.addEventListener("input", () => {
  typed = true;
  menu.value = "";
  keepText();
  scheduleDerive();
});
menu.addEventListener("change", () => chooseExample(menu.value));
exerciseBox.addEventListener("change", derive);

// The user's text first, derived at once (the examples may be slow or fail); the first
// example only for an editor never used here, and not over text typed while the examples
// were on their way.
const restored = storedText();
if (restored !== null) {
  editor.value = restored;
  derive();
}
loadExamples().then(
  () => {
    if (restored === null && !typed) {
      chooseExample(FIRST_EXAMPLE);
    } else {  // the menu names the example the text is, if it is one
      const same = examples.find((entry) => entry.text === editor.value);
      menu.value = same ? same.name : "";
    }
  },
  (error) => showError("the examples could not be loaded: " + error.message),
);
