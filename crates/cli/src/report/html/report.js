// wogan report's one script: sortable tables, the failing roads' filter, and a road's detail.
// Everything it shows is in the page; it fetches nothing.
"use strict";
(function () {
  const data = JSON.parse(document.getElementById("road-data").textContent);
  const roads = data.roads;
  const svgNs = "http://www.w3.org/2000/svg";

  for (const element of document.querySelectorAll(".needs-script")) element.hidden = false;

  // Sorting: a header's click sorts its table's rows by that column, again the other way. Each
  // column's keys are read from the cells once, at its first sort.
  function cellKey(row, column, numeric) {
    const text = row.cells[column] ? row.cells[column].textContent : "";
    if (!numeric) return text;
    const value = parseFloat(text.replace(/^#/, ""));
    return Number.isNaN(value) ? -Infinity : value;
  }
  for (const table of document.querySelectorAll("table.sortable")) {
    const headers = Array.from(table.tHead.rows[0].cells);
    const body = table.tBodies[0];
    const original = Array.from(body.rows);
    const keys = new Map();
    headers.forEach((header, column) => {
      header.tabIndex = 0;
      const sort = () => {
        const ascending = header.getAttribute("aria-sort") !== "ascending";
        for (const other of headers) other.removeAttribute("aria-sort");
        header.setAttribute("aria-sort", ascending ? "ascending" : "descending");
        if (!keys.has(column)) {
          const numeric = header.classList.contains("num");
          keys.set(column, original.map((row) => cellKey(row, column, numeric)));
        }
        const key = keys.get(column);
        const order = original.map((row, index) => index);
        order.sort((a, b) => (key[a] < key[b] ? -1 : key[a] > key[b] ? 1 : a - b) * (ascending ? 1 : -1));
        const fragment = document.createDocumentFragment();
        for (const index of order) fragment.appendChild(original[index]);
        body.appendChild(fragment);
        table.dispatchEvent(new Event("sorted"));
      };
      header.addEventListener("click", sort);
      header.addEventListener("keydown", (event) => { if (event.key === "Enter") sort(); });
    });
  }

  // The failing roads: filtered, and shown a page at a time (the first PAGE rows that match, in
  // the table's order, then PAGE more on request), so that a page of 10,000 roads lays out only
  // the rows in view. Without scripts every row shows (the class "js" is never set).
  const PAGE = 500;
  const table = document.getElementById("failing-roads");
  const body = table.tBodies[0];
  const rows = Array.from(body.rows);
  const facts = new Map(rows.map((row) => {
    const cells = row.cells;
    const group = data.groups[Number(cells[0].textContent.slice(1)) - 1] || "";
    return [row, {
      text: (group + " " + cells[0].textContent + " " + cells[1].textContent + " #" + cells[2].textContent).toLowerCase(),
      side: cells[4].textContent,
      bolp: parseFloat(cells[3].textContent),
    }];
  }));
  const text = document.getElementById("filter-text");
  const side = document.getElementById("filter-side");
  const bolp = document.getElementById("filter-bolp");
  const count = document.getElementById("filter-count");
  const more = document.getElementById("filter-more");
  let limit = PAGE;
  function refresh() {
    const words = text.value.trim().toLowerCase().split(/\s+/).filter(Boolean);
    const wanted = side.value;
    const least = parseFloat(bolp.value) || 0;
    let matching = 0;
    for (const row of body.rows) {
      const fact = facts.get(row);
      const matches = words.every((word) => fact.text.includes(word))
        && (!wanted || fact.side === wanted) && !(fact.bolp < least);
      const show = matches && matching < limit;
      if (matches) matching += 1;
      if (row.classList.contains("shown") !== show) row.classList.toggle("shown", show);
    }
    count.textContent = Math.min(matching, limit) + " shown of " + matching + " matching (" + rows.length + " failing roads)";
    more.hidden = matching <= limit;
  }
  for (const input of [text, side, bolp]) input.addEventListener("input", () => { limit = PAGE; refresh(); });
  more.addEventListener("click", () => { limit += PAGE; refresh(); });
  table.addEventListener("sorted", refresh);
  refresh();

  // A road's detail.
  function element(name, attributes, parent) {
    const node = document.createElementNS(svgNs, name);
    for (const [key, value] of Object.entries(attributes)) node.setAttribute(key, value);
    if (parent) parent.appendChild(node);
    return node;
  }
  function pathOf(points) {
    return points.filter((p) => p[0] !== null && p[1] !== null).map((p) => p[0] + "," + (-p[1])).join(" ");
  }
  function roadPicture(road) {
    const all = road.line.concat(road.exit ? [road.exit] : [], road.trace ? road.trace.xy : [])
      .filter((p) => p[0] !== null && p[1] !== null);
    const xs = all.map((p) => p[0]), ys = all.map((p) => -p[1]);
    const margin = 8;
    const x0 = Math.min(...xs) - margin, y0 = Math.min(...ys) - margin;
    const width = Math.max(...xs) - x0 + margin, height = Math.max(...ys) - y0 + margin;
    const svg = element("svg", { viewBox: [x0, y0, width, height].join(" "), role: "img",
      "aria-label": "the road, where the car left its lane" });
    element("polyline", { points: pathOf(road.line), fill: "none", stroke: "#8a8f98", "stroke-width": 8,
      "stroke-linejoin": "round", "stroke-linecap": "butt" }, svg);
    element("polyline", { points: pathOf(road.line), fill: "none", stroke: "#f3d34a", "stroke-width": 0.3,
      "stroke-dasharray": "2 2" }, svg);
    const start = road.line[0];
    element("circle", { cx: start[0], cy: -start[1], r: 1.5, fill: "#2e8b57" }, svg);
    if (road.trace) {
      element("polyline", { class: "car-path", points: pathOf(road.trace.xy), fill: "none", stroke: "#2557a7",
        "stroke-width": 0.6 }, svg);
    }
    if (road.exit) {
      const [x, y] = road.exit;
      element("path", { class: "lane-exit", d: `M${x - 2},${-y - 2}L${x + 2},${-y + 2}M${x - 2},${-y + 2}L${x + 2},${-y - 2}`,
        stroke: "#c62828", "stroke-width": 0.9 }, svg);
    }
    return svg;
  }
  function bolpPicture(trace) {
    const width = 400, height = 120, left = 34, bottom = 20;
    const svg = element("svg", { viewBox: `0 0 ${width} ${height}`, role: "img", "aria-label": "BOLP along the drive" });
    const end = trace.t[trace.t.length - 1] || 1;
    const x = (t) => left + (t / end) * (width - left - 6);
    const y = (b) => height - bottom - b * (height - bottom - 6);
    element("line", { x1: left, y1: y(0), x2: width - 6, y2: y(0), stroke: "#999" }, svg);
    element("line", { x1: left, y1: y(0), x2: left, y2: y(1), stroke: "#999" }, svg);
    for (const b of [0, 0.5, 1]) {
      const label = element("text", { x: left - 4, y: y(b) + 4, "text-anchor": "end", "font-size": 10 }, svg);
      label.textContent = b;
    }
    const time = element("text", { x: width - 6, y: height - 4, "text-anchor": "end", "font-size": 10 }, svg);
    time.textContent = "time (s), to " + end;
    element("polyline", { points: trace.t.map((t, i) => x(t) + "," + y(trace.bolp[i] || 0)).join(" "),
      fill: "none", stroke: "#c62828", "stroke-width": 1.5 }, svg);
    return svg;
  }
  const detail = document.getElementById("detail");
  function show(index) {
    const road = roads[index], row = document.getElementById("road-" + index);
    if (!road || !row) return;
    row.classList.add("shown");
    for (const selected of table.querySelectorAll("tr[aria-selected]")) selected.removeAttribute("aria-selected");
    row.setAttribute("aria-selected", "true");
    const cells = row.cells;
    detail.replaceChildren();
    const title = document.createElement("h3");
    title.textContent = cells[1].textContent + ", test " + cells[2].textContent;
    detail.appendChild(title);
    const facts = document.createElement("dl");
    const fact = (name, value) => {
      const dt = document.createElement("dt"), dd = document.createElement("dd");
      dt.textContent = name; dd.textContent = value; facts.append(dt, dd);
    };
    fact("group", cells[0].textContent + ": " + (data.groups[Number(cells[0].textContent.slice(1)) - 1] || ""));
    fact("max BOLP", cells[3].textContent);
    fact("lane left by", cells[4].textContent === "–" ? "not recorded" : "the " + cells[4].textContent + " edge");
    fact("length", cells[5].textContent + " m");
    fact("lane exit at", road.exit ? "(" + road.exit[0] + ", " + road.exit[1] + ") m" : "not recorded");
    if (road.trace) {
      fact("driven again", road.trace.driver + ": " + road.trace.outcome + ", max BOLP " + road.trace.max_bolp
        + (road.trace.outcome === "FAIL" ? "" : " (the run recorded FAIL)"));
    }
    detail.appendChild(facts);
    detail.appendChild(roadPicture(road));
    const legend = document.createElement("p");
    legend.className = "legend";
    legend.textContent = "Grey: the road (8 m, two lanes; the car keeps right); green: the start; red cross: where the car left its lane"
      + (road.trace ? "; blue: the car's path driven again." : ".");
    detail.appendChild(legend);
    if (road.trace) {
      const heading = document.createElement("p");
      heading.className = "legend";
      heading.textContent = "BOLP (share of the car outside its lane) along the drive:";
      detail.appendChild(heading);
      detail.appendChild(bolpPicture(road.trace));
    }
    if (location.hash !== "#road-" + index) history.replaceState(null, "", "#road-" + index);
  }
  table.tBodies[0].addEventListener("click", (event) => {
    const row = event.target.closest("tr[data-road]");
    if (row) show(Number(row.dataset.road));
  });
  table.tBodies[0].addEventListener("keydown", (event) => {
    const row = event.target.closest("tr[data-road]");
    if (row && event.key === "Enter") show(Number(row.dataset.road));
  });
  const linked = /^#road-(\d+)$/.exec(location.hash);
  if (linked) show(Number(linked[1]));
})();
