"""The narrow phase of the hand-point queries: which facets of a piece can carry an LP's optimum.

The LPs of cP and sQ are given only the vertices of the facets that can
carry their optimum, so that they are tiny (4 rows, typically 4-30 columns
per block) while their value is unchanged and, when the LP is not
degenerate, so are their duals (fixed by the optimal basis):

* separation (cP of a point outside a piece, `separation_blocks`): the
  optimum lies on a facet facing the point p that the gauge ball
  ``p + v Q`` (v at most an upper bound of cP) can reach;
* a ray ``x0 + r d`` from inside a piece (cP penetration rays ``p - rho q_k``
  and the sQ rays ``c + t (p - c)``, `ray_exits`): the optimum is where the
  ray leaves the piece, on the facets whose plane it crosses last. When it
  leaves through the inside of a single facet the optimum (the exit point)
  and the duals (the facet's plane) are in closed form and no LP is needed.

Every selection uses valid bounds and tolerances on the safe side; a
property test compares the values with brute force over all pieces and all
vertices.
"""

from __future__ import annotations

import numpy as np

from .._jit import kernel
from ..tolerances import DEGENERACY_TOL, VALUE_TOL

#: Settle rays that leave a piece through the inside of one facet in closed form (False: every ray
#: goes to the LP; the tests compare the two).
CLOSED_FORM = True


def separation_blocks(index, P, PQ, bound, rows, pieces):
    """The vertex lists of the separation LP blocks of (point, piece) pairs.

    A facet is kept when it faces p (``n . p + o > 0``) and the gauge ball
    ``p + v Q`` with v <= ``bound`` can reach it: it does not lie beyond the
    facet's plane, and no facet plane of the ball (normal ``-q_k``, offset
    ``bound / 3``) separates them. A pair the ball reaches through no facet
    is not the minimiser and gets no block; should round-off leave a point
    with no facet at all, every facet facing it is kept.

    Parameters
    ----------
    index : PieceIndex
    P : (n, 3) float
    PQ : (n, 4) float
        ``q_k . p``.
    bound : (n,) float
        Upper bound of each point's cP.
    rows, pieces : (m,) int
        The (point, piece) pairs, each point outside its piece.

    Returns
    -------
    used : (m,) bool
        The pairs that get a block.
    counts : (used.sum(),) int
        Vertices of each block.
    ids : (counts.sum(),) int
        The blocks' vertices as rows of ``index.vertices``, ascending within each block.
    """
    rows, pieces = np.asarray(rows, dtype=np.int64), np.asarray(pieces, dtype=np.int64)
    m = len(rows)
    used, counts = np.empty(m, dtype=bool), np.empty(m, dtype=np.int64)
    ids = np.empty(3 * int(np.diff(index.plane_start)[pieces].sum()), dtype=np.int64)
    count = _separation_blocks(P, PQ, bound, rows, pieces, index.planes, index.plane_start, index.facet_nq,
                               index.facet_mq, index.facet_vertices, VALUE_TOL, np.empty(m, dtype=np.int64),
                               np.zeros(len(P), dtype=np.int64), np.full(len(index.vertices), -1, dtype=np.int64),
                               used, counts, ids)
    return used, counts[used], ids[:count]


def ray_exits(index, origin, direction, pieces, closed=None):
    """Where rays ``x0 + r d`` (r >= 0) leave pieces, in closed form where they leave through the inside of one facet.

    The exit facets of a ray are those whose plane it crosses last (within
    `VALUE_TOL`). With a single exit plane (outward normal n, offset o) the
    exit is at ``r = -(n . x0 + o) / (n . d)``, and the duals of the
    coordinate rows of the ray's LP (``max r s.t. x0 + r d = sum lambda_v v,
    sum lambda = 1``) are ``-n / (n . d)``. Faces of a mesh are often split
    into coplanar triangles (a quad into two, a cap into a fan), all of them
    exit facets of the ray: when the exit point lies clearly inside one of
    them (its barycentric weights all above ``10 * DEGENERACY_TOL``) the LP's
    optimal basis is that triangle, unique, and this is the solution the LP
    would give. The other rays need their LP over the exit facets' vertices.

    Parameters
    ----------
    index : PieceIndex
    origin : (m, 3) float
        Ray origins, each inside (or on) its piece.
    direction : (m, 3) float
    pieces : (m,) int
    closed : (m,) bool, optional
        The rays that may be settled in closed form (default: all).

    Returns
    -------
    closed : (m,) bool
        The rays settled in closed form (all False unless `CLOSED_FORM`).
    r : (m,) float
        Exit parameters (meaningful where ``closed``).
    y : (m, 3) float
        Duals ``-n / (n . d)`` (meaningful where ``closed``).
    counts : ((~closed).sum(),) int
        Vertices of the LP block of each other ray.
    ids : (counts.sum(),) int
        Those blocks' vertices (the exit facets' vertices) as rows of ``index.vertices``, ascending within each block.
    """
    pieces = np.asarray(pieces, dtype=np.int64)
    m = len(pieces)
    allowed = np.full(m, CLOSED_FORM) if closed is None else np.asarray(closed, dtype=bool) & CLOSED_FORM
    closed, r, y, counts = np.empty(m, dtype=bool), np.empty(m), np.empty((m, 3)), np.empty(m, dtype=np.int64)
    ids = np.empty(3 * int(np.diff(index.plane_start)[pieces].sum()), dtype=np.int64)
    count = _ray_exits(np.ascontiguousarray(origin, dtype=float), np.ascontiguousarray(direction, dtype=float),
                       pieces, index.planes, index.plane_start, index.vertices, index.facet_vertices, VALUE_TOL,
                       DEGENERACY_TOL, allowed, np.full(len(index.vertices), -1, dtype=np.int64), closed, r, y,
                       counts, ids)
    return closed, r, y, counts[~closed], ids[:count]


@kernel
def _add_vertices(facet_vertices, f, mark, tag, ids, begin, count):
    """Insert facet f's vertices into the sorted block ``ids[begin:count]`` unless marked ``tag``; returns the new count."""
    for a in range(3):
        v = facet_vertices[f, a]
        if mark[v] != tag:
            mark[v] = tag
            at = count
            while at > begin and ids[at - 1] > v:
                ids[at] = ids[at - 1]
                at -= 1
            ids[at] = v
            count += 1
    return count


@kernel
def _separation_blocks(P, PQ, bound, rows, pieces, planes, plane_start, facet_nq, facet_mq, facet_vertices, tol,
                       kept, per_point, mark, used, counts, ids):
    """`separation_blocks` into ``used``, ``counts`` and ``ids`` (``per_point`` zero, ``mark`` -1 on entry); returns the ids' length."""
    m = len(rows)
    # pass 1: the facets each pair keeps; a point that keeps none anywhere keeps every facet facing it
    for e in range(m):
        kept[e] = 0
        i, j = rows[e], pieces[e]
        b = bound[i]
        t = tol * (1.0 + b)
        reach = b / 3.0 + t
        for f in range(plane_start[j], plane_start[j + 1]):
            v = P[i, 0] * planes[f, 0] + P[i, 1] * planes[f, 1] + P[i, 2] * planes[f, 2] + planes[f, 3]
            if v > 0.0 and v + b * facet_nq[f] <= t:
                apart = False
                for k in range(4):
                    if facet_mq[k, f] + PQ[i, k] > reach:
                        apart = True
                if not apart:
                    kept[e] += 1
        per_point[i] += kept[e]
    # pass 2: each used pair's vertex list (the vertices of its facets, ascending)
    count = 0
    for e in range(m):
        i, j = rows[e], pieces[e]
        lost = per_point[i] == 0
        used[e] = False
        counts[e] = 0
        if kept[e] == 0 and not lost:
            continue
        b = bound[i]
        t = tol * (1.0 + b)
        reach = b / 3.0 + t
        begin = count
        for f in range(plane_start[j], plane_start[j + 1]):
            v = P[i, 0] * planes[f, 0] + P[i, 1] * planes[f, 1] + P[i, 2] * planes[f, 2] + planes[f, 3]
            if not v > 0.0:
                continue
            keep = lost
            if not keep and v + b * facet_nq[f] <= t:
                keep = True
                for k in range(4):
                    if facet_mq[k, f] + PQ[i, k] > reach:
                        keep = False
            if keep:
                count = _add_vertices(facet_vertices, f, mark, e, ids, begin, count)
        used[e] = count > begin
        counts[e] = count - begin
    return count


@kernel
def _ray_exits(origin, direction, pieces, planes, plane_start, vertices, facet_vertices, tol, degeneracy, allowed,
               mark, closed, r_out, y, counts, ids):
    """`ray_exits` into ``closed``, ``r_out``, ``y``, ``counts`` and ``ids`` (``mark`` -1 on entry); returns the ids' length."""
    m = len(origin)
    count = 0
    for e in range(m):
        closed[e] = False
        r_out[e] = 0.0
        counts[e] = 0
        y[e, 0] = y[e, 1] = y[e, 2] = 0.0
        j = pieces[e]
        x0, x1, x2 = origin[e, 0], origin[e, 1], origin[e, 2]
        d0, d1, d2 = direction[e, 0], direction[e, 1], direction[e, 2]
        f0, f1 = plane_start[j], plane_start[j + 1]
        r_exit = np.inf
        for f in range(f0, f1):
            a = planes[f, 0] * d0 + planes[f, 1] * d1 + planes[f, 2] * d2
            if a > 0.0:
                r_exit = min(r_exit, -(planes[f, 0] * x0 + planes[f, 1] * x1 + planes[f, 2] * x2 + planes[f, 3]) / a)
        level = r_exit * (1.0 + tol) + tol
        # the exit facets (their vertices make the LP block); the closed form from the first one's plane
        begin = count
        first = -1
        a_first, t = 0.0, 0.0
        coplanar = True
        inner_best = -np.inf
        area0 = area1 = area2 = 0.0
        for f in range(f0, f1):
            a = planes[f, 0] * d0 + planes[f, 1] * d1 + planes[f, 2] * d2
            if not a > 0.0:
                continue
            r = -(planes[f, 0] * x0 + planes[f, 1] * x1 + planes[f, 2] * x2 + planes[f, 3]) / a
            if r > level:
                continue
            if first < 0:
                first, a_first, t = f, a, r
            for c in range(4):
                if abs(planes[f, c] - planes[first, c]) > tol * (1.0 + abs(planes[f, 3])):
                    coplanar = False
            # barycentric weights of the exit point in the facet (signed areas against its normal)
            p0, p1, p2 = x0 + t * d0, x1 + t * d1, x2 + t * d2
            for c in range(3):
                u, w = facet_vertices[f, (c + 1) % 3], facet_vertices[f, (c + 2) % 3]
                u0, u1, u2 = vertices[u, 0] - p0, vertices[u, 1] - p1, vertices[u, 2] - p2
                w0, w1, w2 = vertices[w, 0] - p0, vertices[w, 1] - p1, vertices[w, 2] - p2
                area = ((u1 * w2 - u2 * w1) * planes[f, 0] + (u2 * w0 - u0 * w2) * planes[f, 1]
                        + (u0 * w1 - u1 * w0) * planes[f, 2])
                if c == 0:
                    area0 = area
                elif c == 1:
                    area1 = area
                else:
                    area2 = area
            whole = area0 + area1 + area2
            inner_best = max(inner_best, min(area0 / whole, min(area1 / whole, area2 / whole)))
            count = _add_vertices(facet_vertices, f, mark, e, ids, begin, count)
        if allowed[e] and first >= 0 and coplanar and inner_best > 10.0 * degeneracy * max(1.0, t):
            closed[e] = True
            r_out[e] = t
            for c in range(3):
                y[e, c] = -planes[first, c] / a_first
            count = begin
        else:
            counts[e] = count - begin
    return count


def pick_rows(points, pieces, values, grads, degenerate, n, n_pieces):
    """Each point's row among (point, piece[, k]) results: the max over k of a piece, then the min over pieces.

    cP takes the penetration of a piece as the largest value over the
    directions k and the smallest value over the pieces; sQ (one row per
    piece, ``values`` = -t) the piece the ray leaves last. A tie between
    directions k (the two largest values within `VALUE_TOL`) or between
    pieces with different gradients (the two smallest) makes the derivative
    one-sided: the point is flagged degenerate. Ties are broken by row
    order, then by piece.

    Parameters
    ----------
    points, pieces : (m,) int
        Point and piece of each row.
    values : (m,) float
    grads : (m, 3) float
    degenerate : (m,) bool
        Rows whose own LP is degenerate.
    n, n_pieces : int

    Returns
    -------
    chosen : (n,) int64
        The row of each point (-1 if it has none).
    degenerate : (n,) bool
    """
    chosen, flagged = np.full(n, -1, dtype=np.int64), np.zeros(n, dtype=bool)
    _pick_rows(np.asarray(points, dtype=np.int64), np.asarray(pieces, dtype=np.int64), np.ascontiguousarray(values),
               np.ascontiguousarray(grads), np.asarray(degenerate, dtype=bool), n_pieces, VALUE_TOL,
               np.full(n * n_pieces, -1, dtype=np.int64), np.full(n * n_pieces, -np.inf), np.full(n, -1, dtype=np.int64),
               chosen, flagged)
    return chosen, flagged


@kernel
def _pick_rows(pts, pcs, vals, grads, degs, n_pieces, tol, best, second, runner, chosen, flagged):
    """`pick_rows` into ``chosen`` and ``flagged``; ``best`` (per (point, piece): the row of the largest value,
    -1 on entry), ``second`` (the second largest value, -inf) and ``runner`` (the second smallest pair's row, -1)."""
    n = len(chosen)
    for r in range(len(pts)):
        g = pts[r] * n_pieces + pcs[r]
        b = best[g]
        if b < 0 or vals[r] > vals[b]:
            if b >= 0:
                second[g] = vals[b]
            best[g] = r
        elif vals[r] > second[g]:
            second[g] = vals[r]
    for i in range(n):
        for j in range(n_pieces):
            r = best[i * n_pieces + j]
            if r < 0:
                continue
            if chosen[i] < 0 or vals[r] < vals[chosen[i]]:
                runner[i] = chosen[i]
                chosen[i] = r
            elif runner[i] < 0 or vals[r] < vals[runner[i]]:
                runner[i] = r
        r = chosen[i]
        if r < 0:
            continue
        flagged[i] = degs[r] or abs(second[i * n_pieces + pcs[r]] - vals[r]) <= tol * (1.0 + abs(vals[r]))
        a = runner[i]
        if a >= 0 and abs(vals[a] - vals[r]) <= tol * (1.0 + abs(vals[r])):
            scale = max(abs(grads[r, 0]), max(abs(grads[r, 1]), abs(grads[r, 2])))
            differ = max(abs(grads[a, 0] - grads[r, 0]), max(abs(grads[a, 1] - grads[r, 1]), abs(grads[a, 2] - grads[r, 2])))
            if differ > tol * (1.0 + scale):
                flagged[i] = True
