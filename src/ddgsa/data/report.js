/* ddgsa report: sortable tables, row filters, legend toggles. The page reads without it. */
(function () {
  "use strict";
  document.documentElement.classList.add("js");
  var each = function (list, f) { Array.prototype.forEach.call(list, f); };
  function key(cell) {
    var s = cell.textContent.trim(), v = Number(s);
    return s !== "" && !isNaN(v) ? [0, v, s] : [1, 0, s.toLowerCase()];
  }
  function sortBy(table, i, th) {
    var dir = th.getAttribute("aria-sort") === "ascending" ? -1 : 1;
    each(th.parentNode.cells, function (c) { c.removeAttribute("aria-sort"); });
    th.setAttribute("aria-sort", dir > 0 ? "ascending" : "descending");
    var body = table.tBodies[0], rows = Array.prototype.slice.call(body.rows);
    rows.sort(function (a, b) {
      var x = key(a.cells[i]), y = key(b.cells[i]);
      if (x[0] !== y[0]) { return x[0] - y[0]; }
      if (x[1] !== y[1]) { return dir * (x[1] - y[1]); }
      return dir * (x[2] < y[2] ? -1 : x[2] > y[2] ? 1 : 0);
    });
    rows.forEach(function (r) { body.appendChild(r); });
  }
  each(document.querySelectorAll("table.sortable"), function (table) {
    if (!table.tHead) { return; }
    each(table.tHead.rows[0].cells, function (th, i) {
      th.tabIndex = 0;
      th.title = "sort by this column";
      th.addEventListener("click", function () { sortBy(table, i, th); });
      th.addEventListener("keydown", function (e) {
        if (e.key === "Enter" || e.key === " ") { e.preventDefault(); sortBy(table, i, th); }
      });
    });
  });
  each(document.querySelectorAll("input.filter"), function (input) {
    var table = document.getElementById(input.getAttribute("data-table"));
    input.addEventListener("input", function () {
      var q = input.value.toLowerCase();
      each(table.tBodies[0].rows, function (r) { r.hidden = q !== "" && r.textContent.toLowerCase().indexOf(q) < 0; });
    });
  });
  each(document.querySelectorAll("svg .legend-item"), function (item) {
    item.addEventListener("click", function () {
      var off = item.classList.toggle("off"), k = item.getAttribute("data-series");
      each(item.ownerSVGElement.querySelectorAll('.series[data-series="' + k + '"]'), function (g) {
        g.style.display = off ? "none" : "";
      });
    });
  });
}());
