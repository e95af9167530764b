// Filters of the index: the table is complete without this script; with it, the
// form appears and hides the rows that do not match (data: the JSON index in the page).
(function () {
  "use strict";
  var data = document.getElementById("case-index");
  var form = document.getElementById("filters");
  if (!data || !form) { return; }
  var cases = {};
  JSON.parse(data.textContent).forEach(function (c) { cases[c.id] = c; });
  var rows = Array.prototype.slice.call(document.querySelectorAll("tr[data-case]"));
  var shown = document.getElementById("shown");

  function value(name) { return form.elements[name].value.trim().toLowerCase(); }

  function matches(c) {
    var text = value("text"), author = value("author"), topic = form.elements.topic.value;
    var bracket = form.elements.bracket.value, verdict = form.elements.verdict.value;
    var from = parseInt(value("year-from"), 10), to = parseInt(value("year-to"), 10);
    if (text && (c.id + " " + c.title + " " + c.aliases.join(" ")).toLowerCase().indexOf(text) < 0) { return false; }
    if (author && (c.authors.join(" ") + " " + c.citation).toLowerCase().indexOf(author) < 0) { return false; }
    if (topic && c.topic !== topic) { return false; }
    if (bracket && c.bracket !== bracket) { return false; }
    if (verdict === "not audited" && c.summary !== "not audited") { return false; }
    if (verdict && verdict !== "not audited" && c.verdicts.indexOf(verdict) < 0) { return false; }
    if (!isNaN(from) && (c.year === null || c.year < from)) { return false; }
    if (!isNaN(to) && (c.year === null || c.year > to)) { return false; }
    return true;
  }

  function update() {
    var n = 0;
    rows.forEach(function (row) {
      var ok = matches(cases[row.getAttribute("data-case")]);
      row.hidden = !ok;
      if (ok) { n += 1; }
    });
    shown.textContent = n + " of " + rows.length + " cases shown.";
  }

  form.hidden = false;
  form.addEventListener("input", update);
  form.addEventListener("change", update);
  form.addEventListener("reset", function (event) {
    // cleared here, then filtered at once (the browser would reset after this event)
    event.preventDefault();
    Array.prototype.forEach.call(form.elements, function (field) {
      if (field.tagName === "SELECT") { field.selectedIndex = 0; }
      else if (field.tagName === "INPUT") { field.value = ""; }
    });
    update();
  });
  form.addEventListener("submit", function (event) { event.preventDefault(); });
  update();
}());
