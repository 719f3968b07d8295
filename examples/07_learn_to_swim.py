"""07 - Learn a closed-loop controller for the eel by reinforcement learning, and compare it with
the shipped gait in the same environment.

Shows the Gymnasium environment (``aquagait.envs``, the ``gym`` extra): the
eel swims in the coupled fluid, and at every control step (1/30 s) a policy
sees its joints, its velocity, its heading and the gait's clock, and
corrects the shipped gait's joint targets (``action="residual"``: an action
of zero swims the shipped gait exactly). The reward is the speed ahead less
the actuators' power over m g (``aquagait.envs.swim``).

The learner is Augmented Random Search (ARS V2-t: Mania, Guy and Recht 2018,
"Simple random search provides a competitive approach to reinforcement
learning"): a linear policy on normalized observations, improved along the
random directions whose perturbed episodes (one each way) did best. It needs
nothing beyond NumPy, and runs the two episodes of a direction at once on
two processes (Gymnasium's ``AsyncVectorEnv``). Any RL library that speaks
Gymnasium (Stable-Baselines3, CleanRL, ...) trains on the same environment.

Prints each iteration's returns, then the learned policy against the shipped
gait over the training episode and a longer one: return, distance, speed,
cost of transport. Writes ``policy.npz`` (the matrix and the observation
normalization), ``training.csv`` and ``comparison.json``.

Run:  python examples/07_learn_to_swim.py [--iterations 40] [--directions 4] [--seconds 3]
          [--seed 0] [--out runs/ex07]
(``--steps N``: episodes of N control steps, one iteration, for a quick look.)
"""

from __future__ import annotations

import argparse
import csv
import json
import time
from pathlib import Path

import gymnasium as gym
import numpy as np

from aquagait.envs import ENV_ID, SwimEnv

SETTINGS = {"creature": "eel2d", "task": "forward", "action": "residual"}


class LinearPolicy:
    """``a = clip(M (x - mean) / std, -1, 1)``: ARS's linear policy on normalized observations,
    with the running mean and spread of every observation seen (Welford's update)."""

    def __init__(self, observations: int, actions: int):
        self.matrix = np.zeros((actions, observations))
        self.count, self.mean, self.square = 0, np.zeros(observations), np.zeros(observations)

    @property
    def std(self) -> np.ndarray:
        spread = self.square / max(self.count - 1, 1)
        return np.sqrt(np.where(spread > 1e-12, spread, 1.0))

    def act(self, obs: np.ndarray, matrix: np.ndarray | None = None) -> np.ndarray:
        matrix = self.matrix if matrix is None else matrix
        return np.clip(matrix @ ((obs - self.mean) / self.std), -1.0, 1.0)

    def observe(self, states: np.ndarray) -> None:
        for x in states:
            self.count += 1
            delta = x - self.mean
            self.mean = self.mean + delta / self.count
            self.square = self.square + delta * (x - self.mean)


def paired_episodes(envs, policy: LinearPolicy, plus, minus, seed: int):
    """One episode with ``plus`` and one with ``minus`` at once, on the two environments of
    ``envs``; their returns and every observation seen."""
    obs, _ = envs.reset(seed=seed)
    returns, seen = np.zeros(2), [obs]
    while True:
        actions = np.stack([policy.act(obs[0], plus), policy.act(obs[1], minus)])
        obs, reward, terminated, truncated, _ = envs.step(actions)
        returns += reward
        seen.append(obs)
        if np.any(terminated | truncated):
            return returns, np.concatenate(seen)


def evaluate(policy: LinearPolicy | None, seconds: float) -> dict:
    """One episode of ``seconds``: the policy, or the shipped gait alone (None)."""
    env = SwimEnv(**SETTINGS, seconds=seconds)
    obs, _ = env.reset(seed=0)
    start, total = env.pose.position.copy(), 0.0
    while True:
        action = np.zeros(env.action_space.shape) if policy is None else policy.act(obs)
        obs, reward, terminated, truncated, info = env.step(action)
        total += reward
        if terminated or truncated:
            break
    distance = float(np.linalg.norm(env.pose.position - start))
    mass = env.creature.model.mass
    return {
        "return": total,
        "distance_m": distance,
        "speed_m_per_s": distance / info["time"],
        "energy_J": info["energy"],
        "cost_of_transport_J_per_kg_m": info["energy"] / (mass * distance),
    }


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--iterations", type=int, default=40, help="ARS updates")
    parser.add_argument("--directions", type=int, default=4, help="random directions per update")
    parser.add_argument("--best", type=int, default=2, help="directions kept per update")
    parser.add_argument("--step-size", type=float, default=0.02, help="ARS's alpha")
    parser.add_argument("--noise", type=float, default=0.05, help="ARS's nu")
    parser.add_argument("--seconds", type=float, default=3.0, help="training episode [s]")
    parser.add_argument("--eval-seconds", type=float, default=6.0, help="longer test [s]")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", default="runs/ex07", help="where the results go")
    parser.add_argument("--steps", type=int, help="episodes of this many control steps only")
    args = parser.parse_args(argv)
    quick = args.steps is not None
    seconds = args.steps / 30 if quick else args.seconds
    iterations, directions = (1, 1) if quick else (args.iterations, args.directions)
    best = min(args.best, directions)

    envs = gym.make_vec(ENV_ID, num_envs=2, vectorization_mode="async", seconds=seconds,
                        **SETTINGS)  # fmt: skip
    rng = np.random.default_rng(args.seed)
    policy = LinearPolicy(envs.single_observation_space.shape[0], envs.single_action_space.shape[0])
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    log, began = [], time.perf_counter()
    try:
        for iteration in range(iterations):
            deltas = rng.standard_normal((directions, *policy.matrix.shape))
            results, seen = [], []
            for delta in deltas:
                step = args.noise * delta
                returns, states = paired_episodes(envs, policy, policy.matrix + step,
                                                  policy.matrix - step, seed=args.seed)  # fmt: skip
                results.append(returns)
                seen.append(states)
            results = np.array(results)
            top = np.argsort(results.max(axis=1))[::-1][:best]
            spread = results[top].std() or 1.0
            update = ((results[top, 0] - results[top, 1])[:, None, None] * deltas[top]).sum(0)
            policy.matrix = policy.matrix + args.step_size / (best * spread) * update
            policy.observe(np.concatenate(seen))
            row = {"iteration": iteration + 1, "mean_return": float(results.mean()),
                   "best_return": float(results.max()),
                   "minutes": (time.perf_counter() - began) / 60}  # fmt: skip
            log.append(row)
            print(
                f"iteration {row['iteration']:3d}: returns mean {row['mean_return']:.3f}, "
                f"best {row['best_return']:.3f} ({row['minutes']:.1f} min)", flush=True,
            )  # fmt: skip
    finally:
        envs.close()
    trained = (time.perf_counter() - began) / 60

    np.savez(out / "policy.npz", matrix=policy.matrix, mean=policy.mean, std=policy.std)
    with open(out / "training.csv", "w", newline="") as file:
        writer = csv.DictWriter(file, fieldnames=list(log[0]))
        writer.writeheader()
        writer.writerows(log)
    tests = [seconds] if quick else [seconds, args.eval_seconds]
    comparison = {"settings": {**SETTINGS, **vars(args)}, "training_minutes": trained}
    for length in tests:
        comparison[f"{length:g} s"] = {"shipped gait": evaluate(None, length),
                                       "learned": evaluate(policy, length)}  # fmt: skip
        for name, figures in comparison[f"{length:g} s"].items():
            print(f"{length:g} s, {name:>12}: return {figures['return']:.3f}, distance "
                  f"{figures['distance_m']:.3f} m, {figures['speed_m_per_s']:.3f} m/s, cost of "
                  f"transport {figures['cost_of_transport_J_per_kg_m']:.3f} J/(kg m)")  # fmt: skip
    (out / "comparison.json").write_text(json.dumps(comparison, indent=2) + "\n")
    print(f"trained {trained:.1f} min; wrote {out}/policy.npz, training.csv, comparison.json")


if __name__ == "__main__":
    main()
