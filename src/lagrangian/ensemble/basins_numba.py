"""The labelling of basins of attraction between chunks of map iterations, compiled by numba.

:mod:`lagrangian.ensemble.basins` integrates the members still searching by a chunk of
iterations of the map (the strobe map, or the flow sampled at a fixed interval) and
hands the new points here: :func:`label` walks each member's points in order, member
after member (not in parallel: a cell one member labels is seen by the next one at once,
so two members converging together find one attractor, not two), through the recurrence
state machine of Attractors.jl's ``AttractorsViaRecurrences``:

- a point outside the box of cells for ``lost`` iterations in a row: no attractor (-1);
- a point in a cell of attractor k for ``hits`` iterations in a row: attractor k;
- a point in a cell of k's basin, for ``basin_hits`` iterations in a row: attractor k
  (most starts end so, long before they are near the attractor: Attractors.jl's basin
  cells).  A cell is k's basin when the starts labelled that passed it (each start's
  last ``trail`` cells are remembered when it is labelled: ``seen``) all went to k; where
  starts of two attractors passed (MIXED: a cell on a fractal basin boundary holds points
  of both), no basin hit is counted.  Attractors.jl gives the cell to the first start
  labelled that passed it for good, and a later start of the other basin that runs
  through such cells is mislabelled: 0.7 % of the driven pendulum's starts at A = 1.073,
  where now none of 20,000 differ from the same map iterated 300 periods
  (benchmarks/basins_labeller.py);
- a point in a cell the member itself visited counts one recurrence; after
  ``recurrences`` of them the member is on an attractor not yet known: it gets the next
  label and goes on ``locate`` more iterations, marking each cell it lands in as that
  attractor's and keeping the points (for the attractor's period and representative
  points);
- ``max_iterations`` iterations without any of that, or a point that is not finite: -1.

A cell holds -1 (never visited), k >= 0 (a cell of attractor k), or -(id + 2): a member
(by its id, the place of its start in the order the starts are taken) that visited it
while searching; a member that finds its own mark there has been there before.  Outside
k's basin cells, the mark of a member since labelled, or of one still searching that was
taken after this one, is taken over (the cell is new to this one); the mark of one still
searching that was taken before it is left alone.  So the earliest start still
searching runs as it would alone, as each start does in Attractors.jl, which runs them
one after another: members that share the cells of one orbit cannot keep wiping each
other's marks (with a chunk of iterations no longer than the orbit's period none of them
would ever see its own mark again).  The module goes
into the code cache as it is (``package_text``), where numba keeps its machine code;
importing :mod:`lagrangian.ensemble.basins` does not import it.
"""

import math

from numba import njit

#: A member's status: still searching, locating a new attractor, or done (>= 0, -1).
SEARCHING = -2
LOCATING = -3
#: A cell's ``seen``: no labelled start passed it yet; starts of more than one attractor did.
UNSEEN, MIXED = -1, -2


@njit(cache=True)
def cell_of(point, which, lows, widths, sizes, angles, centres):  # pragma: no cover
    """The flat index of the cell of ``point`` (the state), -1 outside the box, -2 not finite."""
    index = 0
    for d in range(which.shape[0]):
        x = point[which[d]]
        if x != x or math.isinf(x):
            return -2
        if angles[d]:
            x = centres[d] - math.pi + (x - centres[d] + math.pi) % (2 * math.pi)
        k = math.floor((x - lows[d]) / widths[d] + 0.5)
        if k < 0 or k >= sizes[d]:
            return -1
        index = index * sizes[d] + k
    return index


@njit(cache=True)
def root(alias, k):  # pragma: no cover - compiled by numba
    """The attractor that attractor k was found to be (itself, unless merged)."""
    while alias[k] != k:
        k = alias[k]
    return k


@njit(cache=True)
def run_length(counters, b, run, value):  # pragma: no cover - compiled by numba
    """Start b's run of iterations in a row on ``value``: column ``run`` counts it, column
    ``run + 1`` holds the value; a new value starts a new run of 1."""
    if counters[b, run] > 0 and counters[b, run + 1] == value:
        counters[b, run] += 1
    else:
        counters[b, run] = 1
        counters[b, run + 1] = value
    return counters[b, run]


@njit(cache=True)
def settle(b, value, status, counters, seen, trail, alias):  # pragma: no cover
    """Member b labelled ``value``; when it is an attractor, each cell of the member's trail
    has now been passed by a start of it (``seen``: that attractor's, or MIXED when a start
    of another one passed there before)."""
    status[b] = value
    if value < 0:
        return
    k = root(alias, value)
    for i in range(min(counters[b, 7], trail.shape[1])):
        c = trail[b, i]
        before = seen[c]
        if before == UNSEEN:
            seen[c] = k
        elif before >= 0 and root(alias, before) != k:
            seen[c] = MIXED


@njit(cache=True)
def label(
    points, ids, status, counters, cells, which, lows, widths, sizes, angles, centres,
    settings, found, kept, alias, done, seen, trail,
):  # pragma: no cover - compiled by numba  # fmt: skip
    """Walk the new points (B, m, C) of the B members in order (see the module).

    ``status`` (B,): per member SEARCHING, LOCATING, a label >= 0 or -1; ``counters``
    (B, 8): iterations, recurrences, hits in a row, the label hit, iterations outside
    in a row, basin hits in a row, the basin hit (while locating: the points kept in the
    second, the new label in the fourth), the cells put in the trail; ``settings``:
    recurrences, hits, lost, max_iterations, locate, basin hits; ``done`` (every start's
    id): the label of each start done, else < 0; ``found`` (1,): the attractors so far;
    ``kept`` (A, locate, m): each attractor's located points (a member past A attractors
    gets -1); ``alias`` (A,): the attractor each is (a new one that lands in the cells of
    one found before is that one: one attractor found by two members at once, from two of
    its cells, is merged as soon as either sees the other's cells); ``seen`` (cells,):
    UNSEEN, the attractor of every labelled start that passed the cell, or MIXED;
    ``trail`` (B, T): the cells of each member's searching points (the last T of them).
    """
    recurrences, hits, lost, limit, locate, basin_hits = (
        settings[0], settings[1], settings[2], settings[3], settings[4], settings[5]
    )  # fmt: skip
    capacity = kept.shape[0]
    length = trail.shape[1]
    count, m, chunk = points.shape
    for b in range(count):
        mark = -(ids[b] + 2)
        for j in range(chunk):
            state = status[b]
            if state >= -1:
                break
            point = points[b, :, j]
            counters[b, 0] += 1
            if state == SEARCHING and counters[b, 0] > limit:
                status[b] = -1  # the check at the end is skipped by the paths that continue
                break
            cell = cell_of(point, which, lows, widths, sizes, angles, centres)
            if cell == -2:
                status[b] = -1
                break
            if state == LOCATING:
                new = counters[b, 3]
                if cell >= 0 and cells[cell] < 0:
                    cells[cell] = new
                elif cell >= 0:
                    mine, other = root(alias, new), root(alias, cells[cell])
                    if mine != other:
                        alias[max(mine, other)] = min(mine, other)
                at = counters[b, 1]
                for i in range(m):
                    kept[new, at, i] = point[i]
                counters[b, 1] = at + 1
                if at + 1 >= locate:
                    settle(b, new, status, counters, seen, trail, alias)
                continue
            if cell == -1:
                counters[b, 2] = 0
                counters[b, 5] = 0
                counters[b, 4] += 1
                if counters[b, 4] >= lost:
                    status[b] = -1
                    break
            else:
                counters[b, 4] = 0
                trail[b, counters[b, 7] % length] = cell
                counters[b, 7] += 1
                value = cells[cell]
                if value >= 0:
                    counters[b, 5] = 0
                    value = root(alias, value)
                    if run_length(counters, b, 2, value) >= hits:
                        settle(b, value, status, counters, seen, trail, alias)
                        break
                else:
                    counters[b, 2] = 0
                    basin = seen[cell]
                    if basin >= 0:  # a cell of one attractor's basin: only its starts passed
                        if run_length(counters, b, 5, root(alias, basin)) >= basin_hits:
                            settle(b, root(alias, basin), status, counters, seen, trail, alias)
                            break
                        continue
                    counters[b, 5] = 0
                    owner = -value - 2
                    if value <= -2 and value != mark and owner < ids[b] and done[owner] == -2:
                        continue  # an earlier start, still searching, keeps its mark
                    if value == mark:
                        counters[b, 1] += 1
                        if counters[b, 1] >= recurrences:
                            new = found[0]
                            if new >= capacity:
                                status[b] = -1
                                break
                            found[0] = new + 1
                            cells[cell] = new
                            for i in range(m):
                                kept[new, 0, i] = point[i]
                            status[b] = LOCATING
                            counters[b, 1] = 1
                            counters[b, 3] = new
                            if locate <= 1:
                                settle(b, new, status, counters, seen, trail, alias)
                            continue
                    else:
                        cells[cell] = mark
            if counters[b, 0] >= limit:
                status[b] = -1
                break
