"""The narrow phase of the hand-point queries: which facets of a piece can carry an LP's optimum.

The LPs of cP and sQ are given only the vertices of the facets that can
carry their optimum, so that they are tiny (4 rows, typically 4-30 columns
per block) while their value is unchanged and, when the LP is not
degenerate, so are their duals (fixed by the optimal basis):

* separation (cP of a point outside a piece, `separation_vertices`): the
  optimum lies on a facet facing the point p that the gauge ball
  ``p + v Q`` (v at most an upper bound of cP) can reach;
* a ray ``x0 + r d`` from inside a piece (cP penetration rays ``p - rho q_k``
  and the sQ rays ``c + t (p - c)``, `ray_exit`): the optimum is where the
  ray leaves the piece, on the facets whose plane it crosses last. When it
  leaves through the inside of a single facet the optimum (the exit point)
  and the duals (the facet's plane) are in closed form and no LP is needed.

Then `pick_rows` keeps, of the results of a point's pieces, the one that
gives its value. The compiled loops of the two queries live here too, with
the functions they call: `cp_blocks` and `cp_pick` (cP's LP blocks, its
closed-form rays, and each point's result), `sq_rows` (sQ's rays);
`synergrasp.objects.contact_distance` and `synergrasp.objects.scaled_contacts`
call them and own the rest of each query. Every selection uses valid bounds
and tolerances on the safe side (a property test compares the values with
brute force over all pieces and all vertices).
"""

from __future__ import annotations

import numpy as np

from .._jit import helper, kernel

#: Settle rays that leave a piece through the inside of one facet in closed form (False: every ray
#: goes to the LP; the tests compare the two).
CLOSED_FORM = True


@helper
def add_vertices(facet_vertices, f, mark, tag, ids, begin, count):
    """Insert facet f's vertices into the ascending list ``ids[begin:count]`` unless marked ``tag``; returns the new count."""
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


@helper
def separation_vertices(p, pq, bound, j, facing_only, emit, planes, plane_start, facet_nq, facet_mq, facet_vertices,
                        tol, mark, tag, ids, begin):
    """The facets of piece j that can carry the separation optimum of the point p.

    A facet is kept when it faces p (``n . p + o > 0``) and the gauge ball
    ``p + v Q`` with v <= ``bound`` (an upper bound of p's cP) can reach it:
    it does not lie beyond the facet's plane (``n . p + o <= -bound min_k
    n . q_k``), and no facet plane of the ball (normal ``-q_k``, offset
    ``bound / 3``) separates them (``min_t -q_k . t + q_k . p <= bound / 3``
    over the facet's vertices t). A piece the ball reaches through no facet
    is not the point's minimiser. With ``facing_only`` every facet facing p
    is kept instead (for a point that round-off left with no facet in any
    of its pieces).

    Parameters
    ----------
    p : (3,) float
    pq : (4,) float
        ``q_k . p``.
    bound : float
    j : int
    facing_only : bool
    emit : bool
        Append the kept facets' vertices to ``ids`` (ascending, from
        ``begin``; `add_vertices`); else only count the facets.
    planes, plane_start, facet_nq, facet_mq, facet_vertices : arrays of `PieceIndex`
    tol : float
        `VALUE_TOL`.
    mark, tag, ids, begin
        As `add_vertices`.

    Returns
    -------
    int
        The new length of ``ids`` if ``emit``, else the number of facets kept.
    """
    t = tol * (1.0 + bound)
    reach = bound / 3.0 + t
    f0, f1 = plane_start[j], plane_start[j + 1]
    sub, nq = planes[f0:f1], facet_nq[f0:f1]  # loops from 0 over slices compile to much faster code
    x, y, z = p[0], p[1], p[2]
    count = begin if emit else 0
    for f in range(f1 - f0):
        v = x * sub[f, 0] + y * sub[f, 1] + z * sub[f, 2] + sub[f, 3]
        if not v > 0.0:
            continue
        keep = facing_only
        if not keep and v + bound * nq[f] <= t:
            keep = True
            for k in range(4):
                if facet_mq[k, f0 + f] + pq[k] > reach:
                    keep = False
        if keep:
            if emit:
                count = add_vertices(facet_vertices, f0 + f, mark, tag, ids, begin, count)
            else:
                count += 1
    return count


@helper
def ray_exit(x0, d, j, r_exit, allowed, planes, plane_start, vertices, facet_vertices, tol, degeneracy, mark, tag, ids,
             begin, y):
    """Where the ray ``x0 + r d`` (r >= 0, x0 inside or on piece j) leaves the piece.

    The exit facets are those whose plane the ray crosses last (within
    ``tol``). With a single exit plane (outward normal n, offset o) the exit
    is at ``r = -(n . x0 + o) / (n . d)``, and the duals of the coordinate
    rows of the ray's LP (``max r s.t. x0 + r d = sum lambda_v v, sum lambda
    = 1``) are ``-n / (n . d)``. Faces of a mesh are often split into
    coplanar triangles (a quad into two, a cap into a fan), all of them exit
    facets of the ray: when the exit point lies clearly inside one of them
    (its barycentric weights all above ``10 * degeneracy``) the LP's optimal
    basis is that triangle, unique, and this is the solution the LP would
    give.

    Parameters
    ----------
    x0, d : (3,) float
    j : int
    r_exit : float
        The smallest ``-(n . x0 + o) / (n . d)`` over the facets with
        ``n . d > 0`` if the caller has it, else NaN.
    allowed : bool
        The ray may be settled in closed form.
    planes, plane_start, vertices, facet_vertices : arrays of `PieceIndex`
    tol, degeneracy : float
        `VALUE_TOL`, `DEGENERACY_TOL`.
    mark, tag, ids, begin
        As `add_vertices`: the exit facets' vertices are appended to ``ids``.
    y : (3,) float
        Receives the duals when settled in closed form.

    Returns
    -------
    r : float
        The exit parameter if settled in closed form, else NaN (then
        ``ids[begin:count]`` is the vertex list of the ray's LP).
    count : int
        ``begin`` if settled in closed form, else the new length of ``ids``.
    """
    f0, f1 = plane_start[j], plane_start[j + 1]
    sub = planes[f0:f1]
    x0_, x1_, x2_, d0, d1, d2 = x0[0], x0[1], x0[2], d[0], d[1], d[2]
    if r_exit != r_exit:
        r_exit = np.inf
        for f in range(f1 - f0):
            a = sub[f, 0] * d0 + sub[f, 1] * d1 + sub[f, 2] * d2
            if a > 0.0:
                r_exit = min(r_exit, -(sub[f, 0] * x0_ + sub[f, 1] * x1_ + sub[f, 2] * x2_ + sub[f, 3]) / a)
    level = r_exit * (1.0 + tol) + tol
    count = begin
    first = -1
    a_first, t = 0.0, 0.0
    coplanar = True
    inner_best = -np.inf
    area0 = area1 = area2 = 0.0
    for f in range(f1 - f0):
        a = sub[f, 0] * d0 + sub[f, 1] * d1 + sub[f, 2] * d2
        if not a > 0.0:
            continue
        r = -(sub[f, 0] * x0_ + sub[f, 1] * x1_ + sub[f, 2] * x2_ + sub[f, 3]) / a
        if r > level:
            continue
        if first < 0:
            first, a_first, t = f, a, r
        for c in range(4):
            if abs(sub[f, c] - sub[first, c]) > tol * (1.0 + abs(sub[f, 3])):
                coplanar = False
        # barycentric weights of the exit point in the facet (signed areas against its normal)
        p0, p1, p2 = x0_ + t * d0, x1_ + t * d1, x2_ + t * d2
        for c in range(3):
            u, w = facet_vertices[f0 + f, (c + 1) % 3], facet_vertices[f0 + f, (c + 2) % 3]
            u0, u1, u2 = vertices[u, 0] - p0, vertices[u, 1] - p1, vertices[u, 2] - p2
            w0, w1, w2 = vertices[w, 0] - p0, vertices[w, 1] - p1, vertices[w, 2] - p2
            area = ((u1 * w2 - u2 * w1) * sub[f, 0] + (u2 * w0 - u0 * w2) * sub[f, 1]
                    + (u0 * w1 - u1 * w0) * sub[f, 2])
            if c == 0:
                area0 = area
            elif c == 1:
                area1 = area
            else:
                area2 = area
        whole = area0 + area1 + area2
        inner_best = max(inner_best, min(area0 / whole, min(area1 / whole, area2 / whole)))
        count = add_vertices(facet_vertices, f0 + f, mark, tag, ids, begin, count)
    if allowed and first >= 0 and coplanar and inner_best > 10.0 * degeneracy * max(1.0, t):
        for c in range(3):
            y[c] = -sub[first, c] / a_first
        return t, begin
    return np.nan, count


@kernel
def pick_rows(pts, pcs, vals, grads, degs, n_pieces, tol, best, second, runner, chosen, flagged):
    """Each point's row among (point, piece[, k]) results: the max over k of a piece, then the min over pieces.

    cP takes the penetration of a piece as the largest value over the
    directions k and the smallest value over the pieces; sQ (one row per
    piece, values -t) the piece the ray leaves last. A tie between
    directions k (the two largest values within ``tol``) or between pieces
    with different gradients (the two smallest) makes the derivative
    one-sided: the point is flagged. Ties are broken by row order, then by
    piece.

    Parameters
    ----------
    pts, pcs : (m,) int
        Point and piece of each row.
    vals : (m,) float
    grads : (m, 3) float
    degs : (m,) bool
        Rows whose own LP is degenerate.
    n_pieces : int
    tol : float
        `VALUE_TOL`.
    best, second, runner : scratch
        (n * n_pieces,) int -1, (n * n_pieces,) float -inf and (n,) int -1 on entry.
    chosen : (n,) int
        Receives each point's row (-1 on entry; stays -1 for a point with no row).
    flagged : (n,) bool
        Receives the degeneracy of each point (False on entry).
    """
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


@kernel
def cp_blocks(P, PQ, S, cand, bound, pid, Q, planes, plane_start, facet_nq, facet_mq, facet_vertices, vertices, tol,
               degeneracy, closed_form, kept, per_point, mark, y3, n_lead, lead, cost, n_vert, vids, sign, origin, rhs,
               keys, block_point, block_piece, block_sep, closed_point, closed_piece, closed_value, closed_grad,
               closed_witness, counts):
    """The LP blocks of cP (the separation pairs by piece then point, then the penetration rays by piece, k,
    point) and the penetration rays settled in closed form; ``counts`` receives (blocks, lead columns, vertex
    ids, closed rays). Block keys are ``(pid * J + piece) * 5`` (separation) and ``... + 1 + k`` (ray k)."""
    n, J = S.shape
    # counters from the zeroed ``counts`` and flags from a comparison, never literals: a literal argument
    # makes numba compile a helper once more for its literal type
    nb, nl, nv, nc = counts[0], counts[1], counts[2], counts[3]
    tag = counts[0]
    count_only, emit = tol != tol, tol == tol
    # separation (Eq. 1): min sum rho  s.t.  Q^T rho - V^T beta = -p,  sum beta = 1
    for j in range(J):
        for i in range(n):
            if cand[i, j] and S[i, j] > 0.0:
                kept[i * J + j] = separation_vertices(P[i], PQ[i], bound[i], j, count_only, count_only, planes, plane_start,
                                                      facet_nq, facet_mq, facet_vertices, tol, mark, tag, vids, nv)
                per_point[i] += kept[i * J + j]
    for j in range(J):
        for i in range(n):
            if not (cand[i, j] and S[i, j] > 0.0):
                continue
            lost = per_point[i] == 0  # round-off left the point with no facet: keep every facet facing it
            if kept[i * J + j] == 0 and not lost:
                continue  # the gauge ball reaches no facet: not the minimiser
            end = separation_vertices(P[i], PQ[i], bound[i], j, lost, emit, planes, plane_start, facet_nq, facet_mq,
                                      facet_vertices, tol, mark, tag, vids, nv)
            tag += 1
            if end == nv:
                continue
            n_lead[nb], n_vert[nb], sign[nb], keys[nb] = 4, end - nv, -1.0, (pid[i] * J + j) * 5
            for k in range(4):
                for c in range(3):
                    lead[nl + k, c] = Q[k, c]
                cost[nl + k] = 1.0
            for c in range(3):
                origin[nb, c] = P[i, c]
                rhs[nb, c] = -P[i, c]
            block_point[nb], block_piece[nb], block_sep[nb] = i, j, True
            nb += 1
            nl += 4
            nv = end
    # penetration (Eq. 3) for each k: min -rho  s.t.  rho q_k + V^T beta = p,  sum beta = 1: where p - rho q_k leaves
    d = np.empty(3)
    for j in range(J):
        for k in range(4):
            for c in range(3):
                d[c] = -Q[k, c]
            for i in range(n):
                if not (cand[i, j] and S[i, j] <= 0.0):
                    continue
                r, end = ray_exit(P[i], d, j, np.nan, closed_form, planes, plane_start, vertices, facet_vertices, tol,
                                  degeneracy, mark, tag, vids, nv, y3)
                tag += 1
                if r == r:  # closed form: value -r, gradient -y, witness p - r q_k
                    closed_point[nc], closed_piece[nc], closed_value[nc] = i, j, -r
                    for c in range(3):
                        closed_grad[nc, c] = -y3[c]
                        closed_witness[nc, c] = P[i, c] - r * Q[k, c]
                    nc += 1
                    continue
                n_lead[nb], n_vert[nb], sign[nb], keys[nb] = 1, end - nv, 1.0, (pid[i] * J + j) * 5 + 1 + k
                for c in range(3):
                    lead[nl, c] = Q[k, c]
                    origin[nb, c] = P[i, c]
                    rhs[nb, c] = P[i, c]
                cost[nl] = -1.0
                block_point[nb], block_piece[nb], block_sep[nb] = i, j, False
                nb += 1
                nl += 1
                nv = end
    counts[0], counts[1], counts[2], counts[3] = nb, nl, nv, nc


@kernel
def cp_pick(lead_x, witness, y, degenerate, block_point, block_piece, block_sep, closed_point, closed_piece,
             closed_value, closed_grad, closed_witness, n_pieces, tol, pts, pcs, vals, grads, wits, nrms, degs, best,
             second, runner, chosen, flagged, value, grad, nearest, normal, piece, inside):
    """Each point's cP from the rows of its (point, piece[, k]) LP blocks and closed-form rays (`pick_rows`).

    A separation block's value is the sum of its lead variables, its
    gradient -y and its normal y; a penetration block's value is minus its
    lead variable, its gradient y and its normal -y (y its coordinate duals).
    """
    li = 0
    nb = len(block_point)
    for b in range(nb):
        pts[b], pcs[b], degs[b] = block_point[b], block_piece[b], degenerate[b]
        s = -1.0 if block_sep[b] else 1.0
        if block_sep[b]:
            vals[b] = lead_x[li] + lead_x[li + 1] + lead_x[li + 2] + lead_x[li + 3]
            li += 4
        else:
            vals[b] = -lead_x[li]
            li += 1
        for c in range(3):
            grads[b, c] = s * y[b, c]
            nrms[b, c] = -s * y[b, c]
            wits[b, c] = witness[b, c]
    for e in range(len(closed_point)):
        r = nb + e
        pts[r], pcs[r], degs[r], vals[r] = closed_point[e], closed_piece[e], False, closed_value[e]
        for c in range(3):
            grads[r, c] = closed_grad[e, c]
            nrms[r, c] = -closed_grad[e, c]
            wits[r, c] = closed_witness[e, c]
    pick_rows(pts, pcs, vals, grads, degs, n_pieces, tol, best, second, runner, chosen, flagged)
    for i in range(len(chosen)):
        r = chosen[i]
        if r < 0:
            continue
        value[i], piece[i] = vals[r], pcs[r]
        inside[i] = not (r < nb and block_sep[r])
        length = np.sqrt(nrms[r, 0] * nrms[r, 0] + nrms[r, 1] * nrms[r, 1] + nrms[r, 2] * nrms[r, 2])
        for c in range(3):
            grad[i, c] = grads[r, c]
            nearest[i, c] = wits[r, c]
            normal[i, c] = nrms[r, c] / length if length > 0.0 else 0.0


@kernel
def sq_rows(c, U, planes, plane_start, vertices, facet_vertices, candidate_tol, tol, degeneracy, closed_form, depth,
             T, mark, missed, pts, pcs, ts, ys, closed, n_vert, vids, counts):
    """The rows of sQ: one per (point, piece) the ray c + t u leaves last (within ``candidate_tol``).

    A row is settled in closed form (``closed``, ``ts``, ``ys``) when its
    point has a single such piece and the ray leaves it through the inside
    of one facet (`ray_exit`); otherwise its LP's vertex list (``n_vert``
    entries of ``vids``) is given. ``missed`` flags the rays that miss the
    object; ``counts`` receives (rows, vertex ids). ``depth`` (F,) and
    ``T`` (J,) are scratch.
    """
    n, J = len(U), len(plane_start) - 1
    for f in range(len(planes)):  # how far c lies behind each facet plane (< 0: in front)
        depth[f] = -(planes[f, 0] * c[0] + planes[f, 1] * c[1] + planes[f, 2] * c[2] + planes[f, 3])
    rows, nv = counts[0], counts[1]  # from the zeroed counts, not literals (see cp_blocks)
    y = np.empty(3)
    for i in range(n):
        best = -np.inf
        u0, u1, u2 = U[i, 0], U[i, 1], U[i, 2]
        for j in range(J):  # the largest t with c + t u in piece j, -inf when the ray misses it
            f0, f1 = plane_start[j], plane_start[j + 1]
            sub, dep = planes[f0:f1], depth[f0:f1]  # loops from 0 over slices compile to much faster code
            t_hi, t_lo, blocked = np.inf, 0.0, False
            for f in range(f1 - f0):
                a = sub[f, 0] * u0 + sub[f, 1] * u1 + sub[f, 2] * u2
                if a > 0.0:
                    t_hi = min(t_hi, dep[f] / a)
                elif a < 0.0:
                    t_lo = max(t_lo, dep[f] / a)
                elif dep[f] < 0.0:
                    blocked = True  # parallel to the plane, on its outer side
            T[j] = -np.inf if blocked or t_lo > t_hi * (1 + 1e-12) + 1e-12 else t_hi
            best = max(best, T[j])
        missed[i] = not np.isfinite(best)
        if missed[i]:
            continue
        level = best * (1 - candidate_tol) - tol
        alone = 0
        for j in range(J):
            if T[j] >= level:
                alone += 1
        for j in range(J):
            if T[j] < level:
                continue
            pts[rows], pcs[rows] = i, j
            t, end = ray_exit(c, U[i], j, T[j], closed_form and alone == 1, planes, plane_start, vertices, facet_vertices,
                              tol, degeneracy, mark, rows, vids, nv, y)
            closed[rows] = t == t
            ts[rows] = t
            for k in range(3):
                ys[rows, k] = y[k]
            n_vert[rows] = end - nv
            nv = end
            rows += 1
    counts[0], counts[1] = rows, nv
