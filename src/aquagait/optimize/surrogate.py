"""lq-CMA-ES: rank most of a generation by a model, swim only what the model cannot vouch for.

Hansen's global surrogate (2019, "A global surrogate assisted CMA-ES"; pycma's
``cma.fitness_models``) fits a linear, then diagonal-quadratic, then full quadratic
model to the samples evaluated so far, by regression weighted by their ranks
(pycma's `LQModel`, which this module drives). Each generation:

1. swim a first batch of samples (the model's best guesses once it has two points);
2. add them to the model and measure how well it ranks the newest points against
   their true values (Kendall's tau over at least 15 of them);
3. while tau is below 0.85, swim about half as many again, the model's next best,
   and go back to 2;
4. hand CMA-ES the model's values for the whole generation, shifted so that the
   lowest equals the lowest true value (or the true values, when all were swum).

It is pycma's `SurrogatePopulation` with one change: real swims are asked for in
batches of at least ``batch`` samples, the first batch included, so that that
many workers stay busy (pycma asks for one at a time, which leaves all workers
but one idle); a batch that would leave fewer than ``batch`` unswum takes them too.
The batch does not depend on the executor: the same seed gives the same search
serially, in processes, in threads or on Dask.

Nothing here draws a random number, so a search with a surrogate is as
deterministic as one without; the model is part of the run and goes into its
checkpoint.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

TAU_TRUTH = 0.85
"""Kendall's tau between the model's ranking and the true one that lets the rest go unswum."""

MIN_TAU_POINTS = 15
"""Tau is measured over at least this many of the newest points (pycma's ``n_for_tau``)."""

MODEL_SIZE_FACTOR = 1
"""The model keeps at least this many populations of points (pycma's ``model_max_size_factor``)."""


class Surrogate:
    """The model of one group's objective and the rule for which samples to swim.

    Args:
        popsize: the group's population; the model keeps at least that many points.
        batch: the fewest samples swum at a time (fewer only when fewer are left).
    """

    def __init__(self, popsize: int, batch: int):
        from cma.fitness_models import LQModel  # here: workers import this package, not pycma

        if not isinstance(batch, int) or batch < 1:
            raise ValueError(f"the surrogate's batch must be an integer >= 1, got {batch!r}")
        self.model = LQModel()
        self.model.settings.max_absolute_size = MODEL_SIZE_FACTOR * popsize
        self.batch = batch
        self.tau = math.nan  # the last generation's

    def rank(
        self,
        samples: dict[int, np.ndarray],
        swim: Callable[[list[int]], dict[int, float]],
        budget: int | None = None,
    ) -> dict[int, float]:
        """Swim as few of ``samples`` as lets the model rank them all.

        Args:
            samples: the generation's feasible samples by index, in the group's coordinates.
            swim: evaluates the samples of a list of indices (one batch) and returns the
                values of those that succeeded (a failed one is left out, and never
                enters the model).
            budget: the most samples that may be swum (None: all of them).

        Returns:
            A value for every sample that did not fail, to rank the generation by: the
            true values when every sample was swum, else the model's, shifted so that
            their lowest equals the lowest true value. When the budget runs out before the
            model can vouch for the ranking, the true values of those swum (the search
            ends there).
        """
        model, order = self.model, list(samples)
        cap = len(order) if budget is None else min(budget, len(order))
        true: dict[int, float] = {}
        swum: list[int] = []
        first = 1 + max(0.02 * len(order), 3 / model.settings.truncation_ratio - model.size)
        target = max(self.batch, int(first))
        while len(swum) < cap:
            if model.size > 1:  # the model's best guesses first; stable, so ties keep their order
                order.sort(key=lambda i: model.eval(samples[i]))
            size = min(target, cap) - len(swum)
            if cap - len(swum) - size < self.batch:  # a last batch too small to keep all busy
                size = cap - len(swum)
            batch = [i for i in order if i not in swum][:size]
            values = swim(batch)
            swum += batch
            for i in batch:  # in the model's order, so the archive is the same on every executor
                if i in values:
                    true[i] = values[i]
                    model.add_data_row(samples[i], values[i])
            model.sort(len(true))
            points = max(MIN_TAU_POINTS, min(1.2 * len(swum), 0.75 * len(order)))
            self.tau = model.kendall(int(points))
            if self.tau >= TAU_TRUTH:
                break
            target = max(target + math.ceil(target / 2), len(swum) + self.batch)
        model.sort(len(true))
        model.adapt_max_relative_size(self.tau)
        if len(swum) == len(order) or self.tau < TAU_TRUTH or not true:
            return true  # all swum, or the budget ran out first (nothing is told)
        ranked = [i for i in samples if i in true or i not in swum]  # not the failed
        predicted = {i: float(model.eval(samples[i])) for i in ranked}
        shift = min(true.values()) - min(predicted.values())
        return {i: value + shift for i, value in predicted.items()}
