"""Web app chart benchmark: the Live tab in a real browser while a device streams 10 000
samples/s, and the size of the built app.

Starts `twinlink up` on a random loopback port with a temporary data folder, serving the built
web app (TWINLINK_UI_DIR or --ui-dir; else the one in the package: build it first with
`cd ui && npm run build`, this builds nothing). It makes one twin with one device, which streams
batches of 500 samples every 50 ms (two signals) through the device WebSocket, and opens the
twin's Live tab in Debian's chromium (headless, driven by bench/ui_chart.mjs with playwright-core
from ui/node_modules). After a warm-up it measures, for each window length: animation frames
per second, the frame interval (p50/p95/p99/max), long tasks (over 50 ms), the samples per
second the page received, and the renderer main thread's busy time and JS heap.

Prints a table and writes JSON to bench/results/ui-chart-<UTC timestamp>.json (or --json
PATH). Exits 1 when a run failed, 2 when the server, node or chromium could not be started.

    .venv/bin/python bench/ui_chart.py             # 30 s and 5 min windows, 20 s each
    .venv/bin/python bench/ui_chart.py --quick     # 30 s window, 8 s
"""

from __future__ import annotations

import argparse
import asyncio
import gzip
import json
import math
import os
import re
import shutil
import sys
import tempfile
import time
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import httpx

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _live_fleet import make_fleet
from _live_report import relative
from _report import RESULTS, ROOT, machine_info, write_json
from _server import Twinlink
from _ui_feeder import FeedResult, feed

DRIVER = Path(__file__).resolve().parent / "ui_chart.mjs"
PACKAGED_UI = ROOT / "src" / "twinlink" / "web" / "app"
SIGNALS = "telemetry:angle,telemetry:force"

# What a smooth chart means here: 60 Hz frames, none much later than the next vsync, and
# every sample shown (no thinning below the window's rate).
GOALS = {"fps": 55.0, "frame_p95_ms": 20.0, "long_tasks": 0, "received_share": 0.95}


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--quick", action="store_true", help="smoke run: 30 s window, 8 s")
    p.add_argument("--json", type=Path, help="results file (default bench/results/ui-chart-*)")
    p.add_argument("--ui-dir", type=Path, help="the built web app (default TWINLINK_UI_DIR)")
    p.add_argument("--windows", help="window lengths in seconds (30,300; 30 quick)")
    p.add_argument("--seconds", type=float, help="measured seconds per window (20; 8 quick)")
    p.add_argument("--warmup", type=float, default=3.0, help="seconds before measuring (3)")
    p.add_argument("--rate", type=int, default=10_000, help="samples/s the device sends")
    p.add_argument("--batch", type=int, default=500, help="samples per batch (500)")
    p.add_argument("--chromium", default="/usr/bin/chromium", help="the browser binary")
    p.add_argument("--shots", type=Path, help="folder for a screenshot of each run")
    p.add_argument("--profile", action="store_true", help="CPU-profile the page (slows it)")
    p.add_argument(
        "--baseline", action="store_true", help="also measure the first window paused (no data)"
    )
    a = p.parse_args(argv)
    a.windows = [int(w) for w in (a.windows or ("30" if a.quick else "30,300")).split(",")]
    a.seconds = a.seconds or (8.0 if a.quick else 20.0)
    return a


def ui_dir(option: Path | None) -> Path:
    folder = option or Path(os.environ.get("TWINLINK_UI_DIR") or PACKAGED_UI)
    if not (folder / "index.html").is_file():
        raise RuntimeError(f"no built web app in {folder}: run `cd ui && npm run build` first")
    return folder.resolve()


def _gz(path: Path) -> int:
    return len(gzip.compress(path.read_bytes(), compresslevel=9))


def bundle_sizes(folder: Path) -> dict[str, Any]:
    """The entry script and style sheet index.html loads, and the chunks loaded later."""
    html = (folder / "index.html").read_text()
    entry = {Path(m).name for m in re.findall(r'(?:src|href)="[^"]*/assets/([^"]+)"', html)}
    files = sorted((folder / "assets").iterdir())
    sizes: dict[str, Any] = {"main_js": None, "main_css": None, "lazy_js": []}
    for f in files:
        item = {"file": f.name, "bytes": f.stat().st_size, "gzip_bytes": _gz(f)}
        if f.name in entry and f.suffix == ".js":
            sizes["main_js"] = item
        elif f.name in entry and f.suffix == ".css":
            sizes["main_css"] = item
        elif f.suffix == ".js":
            sizes["lazy_js"].append(item)
    return sizes


async def run_driver(
    args: argparse.Namespace, env: dict[str, str], shot: Path | None
) -> dict[str, Any]:
    env = {**os.environ, **env, "BENCH_CHROMIUM": args.chromium}
    if shot:
        env["BENCH_SHOT"] = str(shot)
    if args.profile:
        env["BENCH_PROFILE"] = "1"
    proc = await asyncio.create_subprocess_exec(
        "node", str(DRIVER), env=env, stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE
    )
    try:
        out, err = await asyncio.wait_for(proc.communicate(), args.seconds + args.warmup + 120)
    except TimeoutError:
        proc.kill()
        await proc.wait()
        raise RuntimeError("the browser run did not finish in time") from None
    if proc.returncode != 0:
        raise RuntimeError(f"the browser run failed: {err.decode(errors='replace')[-1500:]}")
    return dict(json.loads(out.decode().strip().splitlines()[-1]))


async def measure_window(
    args: argparse.Namespace, server: Twinlink, slug: str, token: str, window: int, paused: bool
) -> dict[str, Any]:
    """One browser run on the Live tab with `window` while the device streams; `paused`
    clicks Pause first (the page then receives nothing: its cost at rest)."""
    stop, ready = asyncio.Event(), asyncio.Event()
    ws_url = server.url.replace("http://", "ws://", 1)
    feeder = asyncio.create_task(feed(ws_url, token, args.rate, args.batch, stop, ready))
    await asyncio.wait_for(ready.wait(), 30)
    env = {
        "BENCH_URL": server.url,
        "BENCH_TOKEN": server.admin_token,
        "BENCH_PATH": f"/app/twins/{slug}/live?s={SIGNALS}&w={window}",
        "BENCH_SECONDS": str(args.seconds),
        "BENCH_WARMUP_S": str(args.warmup),
    }
    if paused:
        env["BENCH_PAUSED"] = "1"
    name = f"ui-chart-{window}s{'-paused' if paused else ''}.png"
    shot = args.shots / name if args.shots else None
    try:
        page = await run_driver(args, env, shot)
    finally:
        stop.set()
        fed: FeedResult = await feeder
    page["window_s"] = window
    page["paused"] = paused
    page["device"] = {
        "sent_per_s": round(fed.rate),
        "sent": fed.sent,
        "accepted": fed.accepted,
        "late_batches": fed.late_batches,
        "errors": fed.errors[:5],
    }
    page["goals_met"] = {} if paused else goals_met(page, fed.rate)
    return page


def expected_rate(sent_rate: float, max_rate: int | None) -> float:
    """What the page should receive: everything, or under a `max_rate` every n-th of the
    evenly spaced samples (the server keeps one when 1/max_rate s passed since the last)."""
    if not max_rate or max_rate >= sent_rate:
        return sent_rate
    return sent_rate / math.ceil(sent_rate / max_rate)


def goals_met(page: dict[str, Any], sent_rate: float) -> dict[str, bool]:
    expected = expected_rate(sent_rate, page.get("max_rate"))
    return {
        "fps": page["fps"] >= GOALS["fps"],
        "frame_p95_ms": (page["frame_p95_ms"] or 1e9) <= GOALS["frame_p95_ms"],
        "long_tasks": page["long_tasks"] <= GOALS["long_tasks"],
        "received_share": page["samples_per_s"] >= GOALS["received_share"] * expected,
    }


def _kb(n: int | None) -> str:
    return "-" if n is None else f"{n / 1000:.1f} kB"


def _run_lines(r: dict[str, Any]) -> list[str]:
    """A run's row in the table, and what the device sent and the page showed below it."""
    missed = [k for k, ok in r["goals_met"].items() if not ok]
    verdict = (
        "baseline" if r["paused"] else "met" if not missed else "NOT MET: " + ", ".join(missed)
    )
    window = f"{r['window_s']} s" + (" P" if r["paused"] else "")
    long_tasks = f"{r['long_tasks']} / {r['long_task_ms']:.0f} ms"
    row = (
        f"{window:>7} {r['fps']:>6.1f} {r['frame_p50_ms']:>7.1f} "
        f"{r['frame_p95_ms']:>7.1f} {r['frame_p99_ms']:>7.1f} {r['frame_max_ms']:>7.1f} "
        f"{long_tasks:>14} {r['samples_per_s']:>10,.0f} {r['main_thread_busy_pct']:>5.0f}% "
        f"{r['js_heap_mb']:>5.0f} MB  {verdict}"
    )
    thinned = f" (max_rate {r['max_rate']:,}/s)" if r.get("max_rate") else ""
    below = f"        device sent {r['device']['sent_per_s']:,}/s{thinned}; page: {r['stats_text']}"
    return [row, below]


def render(report: dict[str, Any]) -> str:
    head = (
        f"{'window':>7} {'fps':>6} {'p50 ms':>7} {'p95 ms':>7} {'p99 ms':>7} {'max ms':>7} "
        f"{'long tasks':>14} {'samples/s':>10} {'busy':>6} {'heap':>8}  goals"
    )
    rate = f"{report['config']['rate']:,}".replace(",", " ")
    lines = [
        f"Live tab, {rate} samples/s from one device "
        f"({report['config']['batch']} per batch), 2 signals, headless chromium",
        "",
        head,
        "-" * len(head),
    ]
    for run in report["runs"]:
        lines += _run_lines(run)
    b = report["bundle"]
    lazy = ", ".join(f"{x['file']} {_kb(x['gzip_bytes'])}" for x in b["lazy_js"]) or "none"
    lines += [
        "",
        f"goals: fps >= {GOALS['fps']:g}, frame p95 <= {GOALS['frame_p95_ms']:g} ms, no long "
        f"task, >= {GOALS['received_share']:.0%} of the samples sent received (of those a "
        "max_rate keeps, for a long window); P: paused, the page at rest",
        f"bundle (gzip): main JS {_kb(b['main_js']['gzip_bytes'])} "
        f"({_kb(b['main_js']['bytes'])} raw), CSS {_kb(b['main_css']['gzip_bytes'])}; "
        f"loaded later: {lazy}",
    ]
    return "\n".join(lines)


async def benchmark(args: argparse.Namespace, server: Twinlink, report: dict[str, Any]) -> int:
    print("starting twinlink ...", flush=True)
    try:
        await asyncio.to_thread(server.start)
    except RuntimeError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    fleet = await make_fleet(server, "uichart", 1)
    slug, token = fleet.slugs[0], fleet.tokens[0]
    status = 0
    runs = [(w, False) for w in args.windows]
    if args.baseline:
        runs.insert(0, (args.windows[0], True))
    for window, paused in runs:
        what = " paused" if paused else ""
        print(f"window {window} s{what}: measuring {args.seconds:g} s ...", flush=True)
        try:
            report["runs"].append(await measure_window(args, server, slug, token, window, paused))
        except (RuntimeError, OSError, TimeoutError, json.JSONDecodeError) as err:
            print(f"error: {err}", file=sys.stderr)
            report["errors"].append({"window_s": window, "error": str(err)[:2000]})
            status = 1
    return status


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    if shutil.which("node") is None or not Path(args.chromium).exists():
        print("error: node and chromium are needed (apt-get install -y chromium)", file=sys.stderr)
        return 2
    try:
        folder = ui_dir(args.ui_dir)
    except RuntimeError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    os.environ["TWINLINK_UI_DIR"] = str(folder)
    tmp = Path(tempfile.mkdtemp(prefix="twinlink-bench-ui-"))
    server = Twinlink(tmp / "data")
    config = {k: (str(v) if isinstance(v, Path) else v) for k, v in vars(args).items()}
    report: dict[str, Any] = {
        "machine": machine_info(),
        "config": {**config, "ui_dir": str(folder), "signals": SIGNALS},
        "bundle": bundle_sizes(folder),
        "goals": GOALS,
        "runs": [],
        "errors": [],
    }
    t0 = time.perf_counter()
    try:
        status = asyncio.run(benchmark(args, server, report))
    except (RuntimeError, OSError, httpx.HTTPError) as err:
        print(f"error: {err}", file=sys.stderr)
        report["errors"].append({"error": str(err)[:2000]})
        status = 1
    finally:
        server.stop()
        shutil.rmtree(tmp, ignore_errors=True)
    report["seconds"] = round(time.perf_counter() - t0, 1)
    if report["runs"]:
        print(render(report))
    stamp = datetime.now(UTC).strftime("%Y%m%dT%H%M%SZ")
    path = write_json(report, args.json or RESULTS / f"ui-chart-{stamp}.json")
    print(f"\nresults: {relative(path)}")
    return status


if __name__ == "__main__":
    sys.exit(main())
