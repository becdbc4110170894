"""Settings chosen for a frame-time budget (issue 40, part 4): the search behind `pnb_sweep.py
budget`, kept apart from measuring so that it can be tested against an oracle of known costs and
errors (tests/sweep/budget_test.py). budget_command.py measures; this file only decides what to
measure next and what the answer is.

The knob space is a list of knobs, each a name and its candidate values, each value a dict of
settings applied together (a plain knob: one setting; a joint knob: "gi.enabled=true,
gi.technique=probes", settings that only mean something together). Every knob also has the
player's default (no setting at all), so the defaults are a configuration of the space. By
convention each knob's first value is its cheapest: the first value of every knob is the floor,
the cheapest configuration the space declares.

The search (coordinate descent):
1. measure the defaults, then the floor; the budget is absolute, or a ratio to the cheaper of
   the two (measured in the same run, before the search moves: the budget does not drift with
   what the search finds);
2. from each of them that meets the budget, move one knob at a time to each of its values
   (a batch: one knob's values are independent measurements), keep the move with the lowest
   error within the budget (ties: the cheaper), until no single move improves;
   then trades: two single moves at once that, predicted from their own measurements, lower the
   error within the budget (a move that helps but costs too much, paid for by one that saves;
   the `trades` best predicted are measured), and continue from the best real improvement;
   with `pairs`, when neither helps, every value of every pair of knobs at once (knobs that
   interact: neither change helps alone, both together do: many measurements);
3. the answer is the lowest error within the budget over every configuration measured (not only
   where the descent ended), with the Pareto front (cost, error) of all of them.
Every configuration is measured once (a cache on its canonical settings); `max_configs` bounds
the number measured.
"""
import itertools


class NoConfigurationWithinBudget(Exception):
    """Nothing measured meets the budget; the text says what was cheapest."""


class DefaultsFailed(Exception):
    """The defaults could not be measured: nothing to search from or compare with."""


def pareto_front(points):
    """Indices of the (cost, error) points no other point beats in both (both minimised), by
    cost; of equal points the first."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1], i))
    front, best = [], float("inf")
    for i in order:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


def knobs_from_axes(groups):
    """Knobs from a sweep file's axis tables (each already {key: [value text, ...]}): each table
    one knob, its values every combination of its keys, in order (the first: the cheapest)."""
    knobs = []
    for group in groups:
        keys = list(group)
        values = [dict(zip(keys, combo)) for combo in itertools.product(*[group[k] for k in keys])]
        knobs.append({"name": "+".join(keys), "values": values})
    return knobs


def resolve_budget(budget_ms, budget_ratio, start_costs, ratio_to="cheapest"):
    """The budget in ms: `budget_ms`, or `budget_ratio` times the cheapest of `start_costs`
    (the defaults' and the floor's, measured in the same run; None: failed), or with ratio_to
    "defaults" times the first (the defaults': 1 asks for "no slower than the defaults")."""
    if budget_ms is not None:
        return float(budget_ms)
    if ratio_to == "defaults":
        return float(budget_ratio) * start_costs[0]
    measured = [c for c in start_costs if c is not None]
    if not measured:
        raise NoConfigurationWithinBudget("neither the defaults nor the floor could be measured")
    return float(budget_ratio) * min(measured)


def describe(settings):
    """A configuration as one line: "shadows.technique=sdsm gi.cells=32", or "(defaults)"."""
    return " ".join("%s=%s" % kv for kv in sorted(settings.items())) or "(defaults)"


class Search:
    """One budget search. `measure(list of settings dicts)` returns, for each, a dict with
    "cost" and "error" (numbers) or "failed" (the reason); it may measure them in parallel.
    `canonical(settings)` maps settings to the ones that change anything (those equal to the
    player's defaults dropped), so a configuration is measured once however it was reached.
    `fixed`: settings every configuration has."""

    def __init__(self, knobs, measure, budget_ms=None, budget_ratio=None, fixed=None, canonical=None,
                 max_configs=60, pairs=False, trades=4, ratio_to="cheapest", log=None):
        if (budget_ms is None) == (budget_ratio is None):
            raise ValueError("give either a budget in ms or a ratio")
        self.knobs, self.measure, self.fixed = knobs, measure, dict(fixed or {})
        self.budget_ms, self.budget_ratio = budget_ms, budget_ratio
        self.canonical = canonical or (lambda s: s)
        self.max_configs, self.pairs, self.trades, self.ratio_to = max_configs, pairs, trades, ratio_to
        self.log = log or (lambda text: None)
        self.records = {}   # canonical settings (sorted items) -> record
        self.order = []     # the records in the order they were measured
        self.budget = self.defaults = self.floor = None
        self.stopped_at_limit = False

    def settings(self, choice):
        """A choice (knob name -> value index, None: the player's default) as settings."""
        out = dict(self.fixed)
        for knob in self.knobs:
            i = choice.get(knob["name"])
            if i is not None:
                out.update(knob["values"][i])
        return self.canonical(out)

    def evaluate(self, choices):
        """The records of `choices`, measuring (one batch) those not measured yet, at most up to
        max_configs in all; a choice beyond the limit has no record (None)."""
        wanted, batch = [], []
        for choice in choices:
            settings = self.settings(choice)
            key = tuple(sorted(settings.items()))
            wanted.append(key)
            if key not in self.records and key not in [k for k, _, _ in batch]:
                batch.append((key, settings, choice))
        room = self.max_configs - len(self.order)
        if len(batch) > room:
            self.stopped_at_limit = True
            batch = batch[:max(room, 0)]
        if batch:
            for (key, settings, choice), m in zip(batch, self.measure([s for _, s, _ in batch])):
                record = {"settings": settings, "choice": dict(choice), "index": len(self.order)}
                record.update(m)
                self.records[key] = record
                self.order.append(record)
                self.log("  %3d %s: %s" % (record["index"], describe(settings),
                                           record.get("failed") or "%.3f ms, error %.4g" % (m["cost"], m["error"])))
        return [self.records.get(k) for k in wanted]

    def within(self, record):
        return record is not None and "failed" not in record and record["cost"] <= self.budget

    @staticmethod
    def better(a, b):
        """Whether record a beats b: lower error, then lower cost."""
        return (a["error"], a["cost"]) < (b["error"], b["cost"])

    def best_of(self, records, current):
        best = current
        for r in records:
            if self.within(r) and self.better(r, best):
                best = r
        return best

    def moves(self, choice, names):
        """Every choice differing from `choice` in exactly the knobs `names` (each to another value
        or back to the default)."""
        options = []
        for name in names:
            knob = next(k for k in self.knobs if k["name"] == name)
            options.append([i for i in [None] + list(range(len(knob["values"]))) if i != choice.get(name)])
        for combo in itertools.product(*options):
            moved = dict(choice)
            moved.update(zip(names, combo))
            yield moved

    def descend(self, start):
        """Coordinate descent from the record `start` (within the budget): the record it ends at."""
        current = start
        while not self.stopped_at_limit:
            moved, singles = current, []
            for knob in self.knobs:
                moves = list(self.moves(moved["choice"], [knob["name"]]))
                records = self.evaluate(moves)
                singles += [(knob["name"], m[knob["name"]], r) for m, r in zip(moves, records)
                            if r is not None and "failed" not in r]
                best = self.best_of(records, moved)
                if best is not moved:
                    self.log("  move: %s -> error %.4g at %.3f ms" % (describe(best["settings"]), best["error"],
                                                                      best["cost"]))
                    moved = best
            if moved is current:
                moved = self.trade_move(current, singles)
            if moved is current and self.pairs:
                moved = self.pair_move(current)
            if moved is current:
                break
            current = moved
        return current

    def trade_move(self, current, singles):
        """No single move helps, and every single move was measured from `current`: two moves at
        once whose sum, predicted from their single measurements (costs and errors adding up),
        lowers the error within the budget: one knob's move that helps but costs too much, paid
        for by another's that saves. The `trades` best predicted are measured; the best real
        improvement is taken, else `current`."""
        proposals = []
        for (ka, va, a), (kb, vb, b) in itertools.combinations(singles, 2):
            if ka == kb:
                continue
            cost = a["cost"] + b["cost"] - current["cost"]
            error = a["error"] + b["error"] - current["error"]
            if cost <= self.budget and error < current["error"]:
                choice = dict(current["choice"])
                choice[ka], choice[kb] = va, vb
                proposals.append((error, cost, choice))
        proposals.sort(key=lambda p: (p[0], p[1]))
        best = self.best_of(self.evaluate([c for _, _, c in proposals[:self.trades]]), current)
        if best is not current:
            self.log("  trade: %s -> error %.4g at %.3f ms" % (describe(best["settings"]), best["error"], best["cost"]))
        return best

    def pair_move(self, current):
        """No single move helps: the first pair of knobs whose joint move does (knobs that only
        help together), else `current`."""
        for a, b in itertools.combinations([k["name"] for k in self.knobs], 2):
            best = self.best_of(self.evaluate(list(self.moves(current["choice"], [a, b]))), current)
            if best is not current:
                self.log("  pair move: %s -> error %.4g at %.3f ms" % (describe(best["settings"]), best["error"],
                                                                       best["cost"]))
                return best
            if self.stopped_at_limit:
                break
        return current

    def run(self):
        """The search; returns its result (result()). NoConfigurationWithinBudget when nothing
        measured meets the budget."""
        defaults = self.defaults = self.evaluate([{}])[0]
        if defaults is None or "failed" in defaults:
            raise DefaultsFailed("the defaults could not be measured: %s"
                                              % (defaults or {}).get("failed", "no room under max_configs"))
        floor = self.floor = self.evaluate([{k["name"]: 0 for k in self.knobs}])[0]
        floor_cost = floor["cost"] if floor and "failed" not in floor else None
        self.budget = resolve_budget(self.budget_ms, self.budget_ratio, [defaults["cost"], floor_cost], self.ratio_to)
        self.log("budget %.3f ms" % self.budget)
        starts = [r for r in (defaults, floor) if self.within(r)]
        if not starts:
            cheapest = min((r for r in self.order if "failed" not in r), key=lambda r: r["cost"])
            raise NoConfigurationWithinBudget(
                "no configuration meets the budget of %.3f ms: the cheapest measured, %s, costs %.3f ms "
                "(the defaults %.3f ms)" % (self.budget, describe(cheapest["settings"]), cheapest["cost"],
                                            defaults["cost"]))
        for start in starts:
            self.log("descent from %s" % ("the defaults" if start is defaults else "the floor"))
            self.descend(start)
        return self.result()

    def result(self):
        measured = [r for r in self.order if "failed" not in r]
        feasible = [r for r in measured if self.within(r)]
        winner = min(feasible, key=lambda r: (r["error"], r["cost"], r["index"]))
        front = [measured[i] for i in pareto_front([(r["cost"], r["error"]) for r in measured])]
        defaults, floor = self.defaults, self.floor
        return {"budget_ms": self.budget, "budget_given_ms": self.budget_ms, "budget_ratio": self.budget_ratio,
                "ratio_reference_ms": defaults["cost"] if self.ratio_to == "defaults" else
                min(r["cost"] for r in (defaults, floor) if r and "failed" not in r), "ratio_to": self.ratio_to,
                "defaults_on_front": any(r is defaults for r in front),
                "winner": winner, "defaults": defaults, "floor": floor, "front": front,
                "configurations": self.order, "failed": [r for r in self.order if "failed" in r],
                "stopped_at_limit": self.stopped_at_limit, "max_configs": self.max_configs}


def noise_verdict(winner, winner_again, defaults, defaults_again, truth_noise=None):
    """Whether the winner's advantage over the defaults outlives measurement noise, from each
    measured twice in the same run (dicts with cost and error). The cost's noise is the larger
    relative difference of the two repeats; the error's, twice the larger repeat difference, or
    the truth's own noise (in the error's units, when given) if larger. Returns the figures and a
    sentence."""
    def spread(a, b, key):
        return abs(a[key] - b[key])
    cost_w = (winner["cost"] + winner_again["cost"]) / 2
    cost_d = (defaults["cost"] + defaults_again["cost"]) / 2
    err_w = (winner["error"] + winner_again["error"]) / 2
    err_d = (defaults["error"] + defaults_again["error"]) / 2
    cost_noise = max(spread(winner, winner_again, "cost") / max(cost_w, 1e-12),
                     spread(defaults, defaults_again, "cost") / max(cost_d, 1e-12))
    error_noise = max(2 * max(spread(winner, winner_again, "error"), spread(defaults, defaults_again, "error")),
                      truth_noise or 0.0)
    advantage = err_d - err_w
    same = winner["settings"] == defaults["settings"]
    error_real = not same and advantage > error_noise
    # No slower than the defaults: cheaper, or dearer by less than the cost's noise.
    no_slower = cost_w <= cost_d * (1 + cost_noise)
    if same:
        text = "the defaults are the best configuration measured within the budget"
    elif error_real:
        text = ("the winner's error is lower than the defaults' by %.4g, more than the noise (%.4g): "
                "outside noise" % (advantage, error_noise))
    else:
        text = ("the winner's error advantage over the defaults (%.4g) is within noise (%.4g)"
                % (advantage, error_noise))
    text += "; its cost %.3f ms against the defaults' %.3f ms (repeat spread %.0f %%): %s" % (
        cost_w, cost_d, 100 * cost_noise, "no slower than the defaults" if no_slower else "slower than the defaults")
    return {"winner_cost_ms": cost_w, "defaults_cost_ms": cost_d, "winner_error": err_w, "defaults_error": err_d,
            "cost_noise_rel": cost_noise, "error_noise": error_noise, "error_advantage": advantage,
            "advantage_outside_noise": error_real, "no_slower_than_defaults": no_slower, "text": text}
