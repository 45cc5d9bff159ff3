"""Opens a `wogan report --html` page in a real browser (Debian's chromium, headless) and checks
it as a person would use it, through the browser's DevTools protocol over a pipe (standard
library only: no playwright, no websocket):

- the page loads with no console error, no uncaught exception, and no request for anything
  outside the page (it must be self-contained);
- the failing roads' table has as many rows as the run's summary has failures;
- a click on the "max BOLP" header sorts the rows by it, highest first after a second click;
- a click on a row opens that road's detail (its title names the test, a picture of the road;
  with `--expect-trace`, the car's path and its BOLP along the drive);
- a screenshot of the failing roads with a detail open is written (`--screenshot`);
- with `--hostile` (a page of runs whose headers, file names and errors carry HTML, links and
  pictures), that all of it stayed text: the document's title is the page's own, no element
  carries an `on*` attribute, the only scripts are the page's own three, no link leads anywhere
  but the web (`http:`, `https:`), the page (`#…`) or a file beside it, every picture is a data
  URL of the report's own, and the page's script ran (the filter filters).

    python3 scripts/ci/browser_check.py --page DIR/report.html --run RUN.jsonl \
        --screenshot target/ci-artifacts/report-html.png
    python3 scripts/ci/browser_check.py --page DIR/report.html --rows 45 --hostile

Exits 0 when every check holds, 1 naming the first that does not, 2 when the browser cannot be
started or does not answer in time (`--timeout`); the browser is always ended.
"""

import argparse
import base64
import fcntl
import json
import os
import pathlib
import select
import shutil
import subprocess
import sys
import tempfile
import time


class CheckFailed(Exception):
    """A check on the page did not hold."""


class BrowserError(Exception):
    """The browser could not be started, or stopped answering."""


def _above_four(fd: int) -> int:
    """`fd` moved to a descriptor above 4 (closing `fd`)."""
    moved = fcntl.fcntl(fd, fcntl.F_DUPFD, 5)
    os.close(fd)
    return moved


class Browser:
    """Chromium, headless, spoken to over --remote-debugging-pipe (fd 3 in, fd 4 out; messages
    are JSON ended by a NUL byte)."""

    def __init__(self, executable: str, deadline: float) -> None:
        self.deadline = deadline
        self.profile = tempfile.mkdtemp(prefix="wogan-chromium-")
        to_browser_r, self.to_browser = os.pipe()
        self.from_browser, from_browser_w = os.pipe()
        # The child's ends, above 4, so that putting them at 3 and 4 cannot overwrite one another.
        to_browser_r, from_browser_w = (_above_four(fd) for fd in (to_browser_r, from_browser_w))

        def child_fds() -> None:
            os.dup2(to_browser_r, 3)
            os.dup2(from_browser_w, 4)

        args = [executable, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
                "--no-default-browser-check", "--disable-extensions", "--hide-scrollbars",
                "--remote-debugging-pipe", f"--user-data-dir={self.profile}", "about:blank"]
        self.process = subprocess.Popen(args, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                        stderr=subprocess.DEVNULL, preexec_fn=child_fds, pass_fds=(3, 4),
                                        start_new_session=True)
        os.close(to_browser_r)
        os.close(from_browser_w)
        self.buffer = b""
        self.next_id = 0
        self.events = []

    def send(self, method: str, params=None, session=None):
        """Sends a command and waits for its answer; events read meanwhile are kept."""
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        os.write(self.to_browser, json.dumps(message).encode() + b"\0")
        while True:
            reply = self.read()
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    raise BrowserError(f"{method}: {reply['error'].get('message')}")
                return reply.get("result", {})
            self.events.append(reply)

    def read(self):
        """The next message, waiting no later than the deadline."""
        while b"\0" not in self.buffer:
            left = self.deadline - time.monotonic()
            if left <= 0:
                raise BrowserError("the browser did not answer in time")
            ready, _, _ = select.select([self.from_browser], [], [], left)
            if ready:
                chunk = os.read(self.from_browser, 1 << 16)
                if not chunk:
                    raise BrowserError(f"the browser ended (exit status {self.process.poll()})")
                self.buffer += chunk
        message, self.buffer = self.buffer.split(b"\0", 1)
        return json.loads(message)

    def wait_for(self, method: str, session: str):
        """Waits for an event (kept ones first)."""
        for index, event in enumerate(self.events):
            if event.get("method") == method and event.get("sessionId") == session:
                return self.events.pop(index)
        while True:
            event = self.read()
            if event.get("method") == method and event.get("sessionId") == session:
                return event
            self.events.append(event)

    def close(self) -> None:
        """Ends the browser, whatever state it is in, and leaves no process behind."""
        try:
            os.write(self.to_browser, json.dumps({"id": 0, "method": "Browser.close"}).encode() + b"\0")
        except OSError:
            pass
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            os.killpg(self.process.pid, 9)
            self.process.wait()
        for fd in (self.to_browser, self.from_browser):
            try:
                os.close(fd)
            except OSError:
                pass
        shutil.rmtree(self.profile, ignore_errors=True)


def failures_in_summary(run: pathlib.Path) -> int:
    """The failures the run's summary record counts."""
    for line in run.read_text(encoding="utf-8").splitlines():
        record = json.loads(line)
        if record.get("type") == "summary":
            return int(record["failed"])
    raise CheckFailed(f"{run}: no summary record")


# Run in the page: what of the page is not its own (each a string naming it), for --hostile.
FOREIGN = r"""(() => {
  const found = [];
  if (!/^wogan report: \d+ run\(s\), \d+ failing road\(s\)$/.test(document.title))
    found.push("the title is " + JSON.stringify(document.title));
  for (const element of document.querySelectorAll("*"))
    for (const attribute of element.attributes)
      if (attribute.name.toLowerCase().startsWith("on"))
        found.push(element.tagName.toLowerCase() + " has " + attribute.name + "=" + JSON.stringify(attribute.value));
  const scripts = Array.from(document.scripts);
  const own = scripts.length === 3 && scripts.every((s) => !s.hasAttribute("src"))
    && scripts[0].parentNode === document.head && scripts[1].id === "road-data"
    && scripts[1].type === "application/json" && scripts[2].parentNode === document.body
    && scripts[2] === document.body.lastElementChild;
  if (!own) found.push("scripts beyond the page's own: " + scripts.map((s) => s.outerHTML.slice(0, 80)).join(" | "));
  for (const tag of ["iframe", "frame", "object", "embed", "base", "link", "meta[http-equiv]", "form[action]", "svg script"])
    for (const element of document.querySelectorAll(tag)) found.push("a " + tag + ": " + element.outerHTML.slice(0, 80));
  for (const link of document.querySelectorAll("[href]")) {
    const href = link.getAttribute("href");
    const scheme = /^[\u0000-\u0020]*([a-zA-Z][a-zA-Z0-9+.-]*):/.exec(href.replace(/[\t\n\r]/g, ""));
    if (scheme && !/^https?$/i.test(scheme[1])) found.push("a link to " + JSON.stringify(href));
  }
  for (const image of document.querySelectorAll("img, image, source, video, audio, input[type=image]")) {
    const src = image.getAttribute("src") || image.getAttribute("href") || "";
    if (!(image.tagName === "IMG" && image.classList.contains("picture")
          && /^data:image\/(svg\+xml|png);base64,[A-Za-z0-9+\/=]+$/.test(src)))
      found.push("a picture not the report's own: " + image.outerHTML.slice(0, 80));
  }
  return found;
})()"""


def check_hostile(evaluate, rows: int) -> None:
    """The page shows what files said as text (see --hostile), and its own script runs."""
    foreign = evaluate(FOREIGN)
    if foreign:
        raise CheckFailed("what a file said became part of the page: " + "; ".join(foreign[:10]))
    print("browser_check: the title is the page's own; no on* attribute, no script but the page's, "
          "no link but to the web, the page or beside it, no picture but the report's own")
    counted = evaluate("""(() => { const text = document.getElementById('filter-text');
        const count = () => document.getElementById('filter-count').textContent;
        const before = count();
        text.value = 'no such road zz'; text.dispatchEvent(new Event('input'));
        const none = count();
        text.value = ''; text.dispatchEvent(new Event('input'));
        return [before, none, count()]; })()""")
    if not counted[0] or not counted[1].startswith("0 shown of 0 matching") or counted[2] != counted[0] \
            or f"({rows} failing roads)" not in counted[0]:
        raise CheckFailed(f"the page's script does not filter the rows: {counted}")
    print("browser_check: the page's script runs: the filter filters")


def check(browser: Browser, page: pathlib.Path, failures: int, screenshot, expect_trace: bool,
          hostile: bool = False) -> None:
    target = next(t for t in browser.send("Target.getTargets")["targetInfos"] if t["type"] == "page")
    session = browser.send("Target.attachToTarget", {"targetId": target["targetId"], "flatten": True})["sessionId"]
    for domain in ("Page", "Runtime", "Log", "Network"):
        browser.send(f"{domain}.enable", session=session)
    browser.send("Emulation.setDeviceMetricsOverride",
                 {"width": 1400, "height": 1000, "deviceScaleFactor": 1, "mobile": False}, session=session)
    url = page.resolve().as_uri()
    started = time.monotonic()
    browser.send("Page.navigate", {"url": url}, session=session)
    browser.wait_for("Page.loadEventFired", session)
    timings = {"load": time.monotonic() - started}

    def evaluate(expression: str):
        result = browser.send("Runtime.evaluate", {"expression": expression, "returnByValue": True,
                                                   "awaitPromise": True}, session=session)
        if "exceptionDetails" in result:
            raise CheckFailed(f"{expression}: {result['exceptionDetails'].get('text')}")
        return result["result"].get("value")

    def click(selector: str) -> None:
        box = evaluate(f"""(() => {{ const e = document.querySelector({json.dumps(selector)});
            if (!e) return null; e.scrollIntoView({{block: "center"}});
            const r = e.getBoundingClientRect(); return [r.left + r.width / 2, r.top + r.height / 2]; }})()""")
        if box is None:
            raise CheckFailed(f"nothing on the page matches {selector}")
        for kind in ("mousePressed", "mouseReleased"):
            browser.send("Input.dispatchMouseEvent", {"type": kind, "x": box[0], "y": box[1], "button": "left",
                                                      "clickCount": 1}, session=session)

    rows = evaluate("document.querySelectorAll('#failing-roads tbody tr').length")
    if rows != failures:
        raise CheckFailed(f"the failing roads' table has {rows} rows; the run's summary counts {failures} failures")
    print(f"browser_check: {rows} failing-road rows, as the summary counts")
    if hostile:
        check_hostile(evaluate, rows)
    if rows > 1:
        bolp_header = "#failing-roads thead th:nth-child(4)"
        click(bolp_header)
        started = time.monotonic()
        click(bolp_header)
        evaluate("0")  # answered once the sort's click has been handled
        timings["sort"] = time.monotonic() - started
        values = evaluate("Array.from(document.querySelectorAll('#failing-roads tbody tr'), r => parseFloat(r.cells[3].textContent))")
        if values != sorted(values, reverse=True):
            raise CheckFailed(f"two clicks on 'max BOLP' did not sort the rows highest first: {values[:5]}...")
        print("browser_check: the max BOLP column sorts")
    if rows > 0:
        started = time.monotonic()
        click("#failing-roads tbody tr")
        evaluate("0")
        timings["detail"] = time.monotonic() - started
        detail = evaluate("""(() => { const d = document.getElementById('detail');
            const row = document.querySelector('#failing-roads tbody tr');
            return {title: d.querySelector('h3') ? d.querySelector('h3').textContent : null,
                    test: row.cells[2].textContent, pictures: d.querySelectorAll('svg').length,
                    paths: d.querySelectorAll('.car-path').length,
                    selected: row.getAttribute('aria-selected'), hash: location.hash}; })()""")
        if not detail["title"] or not detail["title"].endswith("test " + detail["test"]) or detail["pictures"] < 1:
            raise CheckFailed(f"a click on the first row did not open its detail: {detail}")
        print(f"browser_check: a click opens the detail of {detail['title']} ({detail['hash']})")
        if expect_trace:
            # The first row, highest BOLP after the sort, is among those driven again.
            if detail["paths"] != 1 or detail["pictures"] != 2:
                raise CheckFailed(f"the worst road's detail shows no car path and BOLP picture: {detail}")
            print("browser_check: the detail shows the road with the car's path driven again, and its BOLP")
        evaluate("document.getElementById('failing').scrollIntoView()")
    if screenshot:
        shot = browser.send("Page.captureScreenshot", {"format": "png"}, session=session)
        screenshot.parent.mkdir(parents=True, exist_ok=True)
        screenshot.write_bytes(base64.b64decode(shot["data"]))
        print(f"browser_check: screenshot {screenshot}")
    problems = []
    for event in browser.events:
        method, params = event.get("method"), event.get("params", {})
        if method == "Runtime.exceptionThrown":
            details = params.get("exceptionDetails", {})
            problems.append(f"uncaught: {details.get('exception', {}).get('description') or details.get('text')}")
        elif method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
            problems.append("console error: " + " ".join(str(a.get("value", a.get("description"))) for a in params.get("args", [])))
        elif method == "Log.entryAdded" and params.get("entry", {}).get("level") == "error":
            problems.append(f"browser log: {params['entry'].get('text')}")
        elif method == "Page.javascriptDialogOpening":
            problems.append(f"a dialog opened: {params.get('message')}")
        elif method == "Network.requestWillBeSent":
            requested = params.get("request", {}).get("url", "")
            if requested.split("#")[0] != url and not requested.startswith("data:"):
                problems.append(f"the page requested {requested}")
    if problems:
        raise CheckFailed("; ".join(problems))
    print("browser_check: no console error, no exception, nothing fetched")
    # Figures, not checks (the machine's load counts): wall time of each step, as a user waits.
    print("browser_check: figures: " + ", ".join(f"{step} {seconds * 1e3:.0f} ms" for step, seconds in timings.items()))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--page", type=pathlib.Path, required=True, help="the report.html to open")
    rows = parser.add_mutually_exclusive_group(required=True)
    rows.add_argument("--run", type=pathlib.Path, help="the run file it reports (its summary's failures)")
    rows.add_argument("--rows", type=int, help="the failing roads the page must show (instead of --run)")
    parser.add_argument("--screenshot", type=pathlib.Path, help="write a PNG of the failing roads with a detail open")
    parser.add_argument("--browser", default=shutil.which("chromium") or "chromium", help="the browser [chromium on PATH]")
    parser.add_argument("--expect-trace", action="store_true",
                        help="the worst road was driven again (--traces): its detail must show the car's path")
    parser.add_argument("--hostile", action="store_true",
                        help="the runs carry HTML, links and pictures: check that all of it stayed text")
    parser.add_argument("--timeout", type=float, default=90.0, help="seconds the whole check may take")
    options = parser.parse_args()
    try:
        failures = options.rows if options.run is None else failures_in_summary(options.run)
        browser = Browser(options.browser, time.monotonic() + options.timeout)
    except (OSError, CheckFailed) as error:
        print(f"browser_check: {error}", file=sys.stderr)
        return 2
    try:
        check(browser, options.page, failures, options.screenshot, options.expect_trace, options.hostile)
    except CheckFailed as error:
        print(f"browser_check: FAILED: {error}", file=sys.stderr)
        return 1
    except BrowserError as error:
        print(f"browser_check: {error}", file=sys.stderr)
        return 2
    finally:
        browser.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
