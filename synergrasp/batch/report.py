"""The report page of a batch: per-grasp summary, a gallery of final grasps, the whole table.

``write_report(OUT)`` writes ``OUT/report.html`` and the gallery's pictures under
``OUT/report/KEY/GRASP.png`` (one small 3-D view per plan, drawn by
``synergrasp.viz.plot_grasps``; a picture newer than its result is reused). The page links
every row to its result file; it needs no server and no network.
"""

from __future__ import annotations

import html
import math
import warnings
from pathlib import Path

import numpy as np

from .._files import atomic_path
from ..hand import SynergyHand
from ..planner.result import PlanResult
from .store import COLUMNS, ResultStore, TaskFailure, grasp_summary
from .worker import load_object

_STYLE = """
body { font-family: system-ui, sans-serif; margin: 1.5em; color: #222; }
table { border-collapse: collapse; font-size: 0.85em; margin-bottom: 1.5em; }
th, td { border: 1px solid #ccc; padding: 0.2em 0.5em; text-align: left; }
th { background: #f0f0f0; }
tr.ok td.status { color: #176b2c; } tr.fail td.status { color: #a3261b; }
.gallery { display: flex; flex-wrap: wrap; gap: 0.6em; }
figure { margin: 0; width: 230px; } figure img { width: 230px; border: 1px solid #ddd; }
figcaption { font-size: 0.8em; }
"""


def write_report(out, gallery: int = 48, hand=None) -> Path:
    """Write the report page of a batch's output folder.

    Parameters
    ----------
    out : str or Path
        The output folder of `synergrasp.batch.run`.
    gallery : int
        Most plans shown in the gallery: the successful ones first (in table
        order), then those that found no grasp. 0: no gallery.
    hand : SynergyHand, optional
        The hand that made the plans; default ``SynergyHand.default()``.

    Returns
    -------
    Path
        ``OUT/report.html``.

    Raises
    ------
    FileNotFoundError
        If ``out`` holds no batch results.
    ValueError
        If ``gallery`` is negative, or no result file can be read.

    Warns
    -----
    UserWarning
        For result files that cannot be read (edited or damaged): the page
        names them and leaves them out of its counts.

    Examples
    --------
    An output folder with one plan, written as `synergrasp.batch.run` would:

    >>> import tempfile
    >>> import synergrasp as sg
    >>> store = sg.batch.ResultStore(tempfile.mkdtemp())
    >>> store.check_writable()
    >>> store.write_object("ellipsoid", "ellipsoid", 1.0)
    >>> _ = store.write_result("ellipsoid", "precision", sg.plan(sg.objects.get("ellipsoid"), "precision"))
    >>> page = write_report(store.out, gallery=1)
    >>> page.name, (store.out / "report" / "ellipsoid" / "precision.png").is_file()
    ('report.html', True)
    """
    if not isinstance(gallery, (int, np.integer)) or isinstance(gallery, bool) or gallery < 0:
        raise ValueError(f"gallery must be a whole number >= 0, got {gallery!r}")
    if hand is not None and not isinstance(hand, SynergyHand):
        raise TypeError(f"hand must be the SynergyHand that made the plans (None: the paper's), got "
                        f"{type(hand).__name__} {hand!r}")
    store = ResultStore(out)
    rows, unreadable = store.scan()
    if not rows and unreadable:
        raise ValueError(f"no result in '{store.results}' can be read ({', '.join(str(p) for p in unreadable)}): "
                         f"run `synergrasp batch OBJECTS... --out {out}` again to plan them anew")
    if not rows:
        raise FileNotFoundError(f"no batch results in '{store.results}': run `synergrasp batch OBJECTS... --out {out}` first")
    unreadable = [path.relative_to(store.out).as_posix() for path in unreadable]
    if unreadable:
        warnings.warn(f"{len(unreadable)} result file(s) in '{store.out}' could not be read and are left out of the report "
                      f"({', '.join(unreadable)}): `synergrasp batch` on the same folder plans them again", UserWarning,
                      stacklevel=2)
    pictures, other_hands = _gallery(store, rows, gallery, hand or SynergyHand.default())
    if other_hands:
        warnings.warn(f"{sum(other_hands.values())} plan(s) of the gallery were made with another hand "
                      f"({', '.join(sorted(other_hands))}) and have no picture: write the report with that hand "
                      "(hand=...; on the command line: synergrasp report DIR --hand FILE)", UserWarning, stacklevel=2)
    page = store.out / "report.html"
    with atomic_path(page) as tmp:
        tmp.write_text(_page(store, rows, pictures, unreadable), encoding="utf-8")
    return page


def _gallery(store, rows, count, hand):
    """[(row, picture path relative to OUT or None, note)] for the gallery's plans, and {hand: plans} of the plans
    made with another hand than ``hand``."""
    from ..viz import plot_grasps

    planned = [r for r in rows if r["status"] == "planned"]
    chosen = ([r for r in planned if r["success"]] + [r for r in planned if not r["success"]])[:count]
    objects, shown, other_hands = {}, [], {}
    for row in chosen:
        json_path = store.out / row["file"]
        picture = store.out / "report" / row["object"] / f"{row['grasp']}.png"
        if not (picture.is_file() and picture.stat().st_mtime >= json_path.stat().st_mtime):
            if row["object"] not in objects:
                source = store.object_source(row["object"])
                objects[row["object"]] = load_object(*source)[0] if source else TaskFailure("load error", "no object.json")
            obj = objects[row["object"]]
            if isinstance(obj, TaskFailure):
                shown.append((row, None, f"object not loaded: {obj.reason}"))
                continue
            result = PlanResult.load(json_path)
            if not hand.made(result.hand):
                shown.append((row, None, f"planned with hand {result.hand}: write the report with that hand (hand=; "
                                         "on the command line --hand FILE)"))
                other_hands[result.hand] = other_hands.get(result.hand, 0) + 1
                continue
            picture.parent.mkdir(parents=True, exist_ok=True)
            caption = f"{row['object']}, {row['grasp']}"
            plot_grasps([(result, obj, caption)], hand, picture, columns=1)
        shown.append((row, picture.relative_to(store.out).as_posix(), ""))
    return shown, other_hands


def _cell(value) -> str:
    if isinstance(value, float):
        return "" if math.isnan(value) else f"{value:.4g}"
    return html.escape(str(value))


def _page(store, rows, pictures, unreadable) -> str:
    e = html.escape
    parts = [f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>synergrasp batch: {e(str(store.out))}</title>"
             f"<style>{_STYLE}</style></head><body>",
             f"<h1>Batch report</h1><p>{len(rows)} tasks in <code>{e(str(store.out.resolve()))}</code>; "
             "table: <a href='summary.csv'>summary.csv</a>.</p>"]
    if unreadable:
        parts.append(f"<p class='unreadable'><b>{len(unreadable)} result file(s) could not be read and are left out</b> "
                     f"(not counted below; <code>synergrasp batch</code> on the same folder plans them again): "
                     f"{', '.join(f'<code>{e(name)}</code>' for name in unreadable)}.</p>")
    parts.append("<h2>Per grasp type</h2><table><tr><th>grasp</th><th>tasks</th><th>grasps found</th><th>success</th>"
                 "<th>failed</th><th>timeouts</th><th>median s</th><th>p90 s</th><th>plans/s per worker</th>"
                 "<th>held in MuJoCo / validated</th></tr>")
    for s in grasp_summary(rows):
        held = f"{s['held']} / {s['validated']}" if s["validated"] else "-"
        parts.append(f"<tr><td>{e(s['grasp'])}</td><td>{s['tasks']}</td><td>{s['success']}</td>"
                     f"<td>{100 * s['rate']:.1f} %</td><td>{s['failed']}</td><td>{s['timeouts']}</td>"
                     f"<td>{_cell(s['median_s'])}</td><td>{_cell(s['p90_s'])}</td><td>{_cell(s['plans_per_s'])}</td>"
                     f"<td>{held}</td></tr>")
    parts.append("</table>")
    if pictures:
        parts.append(f"<h2>Final grasps</h2><p>{len(pictures)} plans, the successful ones first.</p><div class='gallery'>")
        for row, picture, note in pictures:
            verdict = "grasp" if row["success"] else "no grasp"
            if row["held"] != "":
                verdict += ", held in MuJoCo" if row["held"] else f", not held in MuJoCo ({e(row['physics'])})"
            caption = (f"<b>{e(row['object'])}</b>, {e(row['grasp'])}: {verdict}, Q {_cell(row['q'])}, "
                       f"{row['contacts']} contacts, {_cell(row['time_s'])} s")
            image = f"<a href='{e(picture)}'><img src='{e(picture)}' alt='{e(row['object'])} {e(row['grasp'])}'></a>" if picture else e(note)
            parts.append(f"<figure>{image}<figcaption>{caption}</figcaption></figure>")
        parts.append("</div>")
    parts.append("<h2>All tasks</h2><table><tr>" + "".join(f"<th>{c}</th>" for c in COLUMNS) + "</tr>")
    for row in rows:
        cls = "ok" if row["success"] else "fail"
        cells = []
        for column in COLUMNS:
            value = _cell(row[column])
            if column == "file":
                value = f"<a href='{e(row['file'])}'>{value}</a>"
            cells.append(f"<td class='{column}'>{value}</td>")
        parts.append(f"<tr class='{cls}'>{''.join(cells)}</tr>")
    parts.append("</table></body></html>")
    return "\n".join(parts)
