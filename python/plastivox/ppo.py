"""PPO for a fixed body's controller, through plastivox.VoxelVecEnv (docs/control.md,
"Learning a controller: PPO vs CMA-ES"). Needs PyTorch (Debian's python3-torch); `import
plastivox` does not import this module or torch.

    python3 -m plastivox.ppo --checkpoint run.pt --steps 2000000 [--seed 1] [--task walk]

The policy is one small MLP shared by every voxel, as the engine's distributed controller is
(docs/control.md): a voxel's 8 features (sin and cos of its clock 2π(f t + φ_i), touch,
strain, velocity x y z, the z of up), normalised by running statistics, give the mean of a
Gaussian on its actuation, with one learned log standard deviation; the action sent is the
sample clipped to [-1, 1]. The critic reads the voxels' mean features and the life's time.
Each iteration collects one whole life in each of the batch's environments (every life has
the same length unless it ends early; steps after an early end are masked out), estimates
advantages by GAE, and takes clipped-objective steps (Schulman et al., "Proximal Policy
Optimization Algorithms", arXiv:1707.06347, 2017; GAE: arXiv:1506.02438). The ratio is taken
per voxel and the clipped objective averaged over voxels (each voxel an agent sharing the
body's advantage): a ratio over 512 independent voxels' joint probability would be clipped
at almost every step.

The end of a life at physics.duration is a true end (the critic sees the time), so both
truncation and termination stop the bootstrap. Every `eval_every` iterations the mean
action (no noise) is run for one life: the champion is the best such life, a deterministic
controller like CMA-ES's samples. Every life simulated, the evaluations' included, counts in
the engine steps.

Checkpoints: after every iteration the whole state (networks, optimiser, normaliser, torch's
random state, counters, the log) is written to a temporary file and renamed over the
checkpoint, so a kill loses at most the iteration in flight; run again with the same
arguments to resume. Determinism: torch runs on torch_threads threads (default 1) and the
environments step bit-identically on any number of threads; with one torch thread a run and
a resumed run give the same bits on one machine and build. With more torch threads, or
another torch build or CPU, the floating-point sums may differ.
"""

import argparse
import json
import math
import os
import time

import numpy as np
import torch
from torch import nn

import plastivox

SENSORS = ["touch", "strain", "velocity", "up", "time"]
FEATURES = 8


def _mlp(inputs, hidden, outputs):
    return nn.Sequential(nn.Linear(inputs, hidden), nn.Tanh(), nn.Linear(hidden, hidden),
                         nn.Tanh(), nn.Linear(hidden, outputs))


class Agent(nn.Module):
    """The shared per-voxel actor and the body's critic."""

    def __init__(self, hidden=16, log_std=math.log(0.5)):
        super().__init__()
        self.actor = _mlp(FEATURES, hidden, 1)
        self.critic = _mlp(FEATURES + 3, hidden, 1)
        self.log_std = nn.Parameter(torch.tensor(float(log_std)))
        # Running statistics of the features (mean, variance, count), updated after each
        # iteration's update so that one iteration sees one normalisation.
        self.register_buffer("feat_mean", torch.zeros(FEATURES, dtype=torch.float64))
        self.register_buffer("feat_var", torch.ones(FEATURES, dtype=torch.float64))
        self.register_buffer("feat_count", torch.zeros((), dtype=torch.float64))

    def normalise(self, feats):
        mean = self.feat_mean.to(feats.dtype)
        std = torch.sqrt(self.feat_var.to(feats.dtype)) + 1e-6
        return ((feats - mean) / std).clamp(-10, 10)

    def observe_stats(self, feats):
        """Merges a batch of raw features (..., FEATURES) into the running statistics."""
        x = feats.reshape(-1, FEATURES).to(torch.float64)
        n, m, v = x.shape[0], x.mean(0), x.var(0, unbiased=False)
        total = self.feat_count + n
        delta = m - self.feat_mean
        self.feat_var.copy_((self.feat_var * self.feat_count + v * n +
                             delta ** 2 * self.feat_count * n / total) / total)
        self.feat_mean.add_(delta * n / total)
        self.feat_count.copy_(total)

    def mean(self, x):
        """x: normalised features (..., voxels, FEATURES) -> the actions' means (..., voxels)."""
        return self.actor(x).squeeze(-1)

    def value(self, x, clock):
        """x as mean() takes it; clock (..., 3): t / duration, sin and cos of 2π f t."""
        return self.critic(torch.cat([x.mean(-2), clock], -1)).squeeze(-1)


class Features:
    """Observations of VoxelVecEnv(sensors=SENSORS) -> per-voxel features and the clock."""

    def __init__(self, env):
        self.n = env._episode.voxels
        self.robot_n = env._episode.robot_voxels
        self.f = env.act_frequency
        self.phase = torch.as_tensor(env.voxel_phase)
        self.duration = env.duration

    def __call__(self, obs):
        o = torch.as_tensor(obs)
        n, r = self.n, self.robot_n
        touch, strain = o[:, :r], o[:, n:n + r]
        vel = o[:, 2 * n:5 * n].reshape(-1, n, 3)[:, :r]
        up_z = o[:, 5 * n:8 * n].reshape(-1, n, 3)[:, :r, 2]
        t = o[:, 8 * n]
        angle = 2 * math.pi * (self.f * t[:, None] + self.phase[None, :])
        feats = torch.stack([torch.sin(angle), torch.cos(angle), touch, strain, vel[..., 0],
                             vel[..., 1], vel[..., 2], up_z], -1)
        body = 2 * math.pi * self.f * t
        clock = torch.stack([t / self.duration, torch.sin(body), torch.cos(body)], -1)
        return feats.float(), clock.float()


def make_env(robot, task, num_envs, every, threads, physics=None, treatment=None):
    return plastivox.VoxelVecEnv(robot, num_envs=num_envs, task=task, physics=physics,
                                 treatment=treatment, sensors=SENSORS, every=every,
                                 threads=threads)


def rollout(agent, vec, feat, gen, deterministic=False):
    """One whole life in each environment. Returns the tensors of the valid steps' data, the
    lives' fitness and the engine steps simulated (an environment whose life ended early
    restarts and runs on until the others end: those steps count too, unused)."""
    obs, _ = vec.reset()
    n_env = vec.num_envs
    alive = np.ones(n_env, dtype=bool)
    fitness = np.zeros(n_env)
    simulated, before = 0, np.zeros(n_env, dtype=np.int64)
    X, C, A, LP, V, R, D, M = [], [], [], [], [], [], [], []
    with torch.no_grad():
        while alive.any():
            raw, clock = feat(obs)
            x = agent.normalise(raw)
            mu = agent.mean(x)
            if deterministic:
                a = mu
            else:
                a = mu + torch.exp(agent.log_std) * torch.randn(mu.shape, generator=gen)
            logp = torch.distributions.Normal(mu, torch.exp(agent.log_std)).log_prob(a)
            actions = a.double().clamp(-1, 1).numpy()
            X.append(raw), C.append(clock), A.append(a), LP.append(logp)
            V.append(agent.value(x, clock))
            M.append(torch.as_tensor(alive.copy()))
            obs, reward, terminated, truncated, infos = vec.step(actions)
            done = terminated | truncated
            R.append(torch.as_tensor(np.where(alive, reward, 0.0), dtype=torch.float32))
            D.append(torch.as_tensor(done))
            ended = alive & done
            fitness[ended] = infos["fitness"][ended]
            now = infos["steps"]
            simulated += int(np.where(now >= before, now - before, now).sum())
            before = now
            alive &= ~done
    return dict(raw=torch.stack(X), clock=torch.stack(C), actions=torch.stack(A),
                logp=torch.stack(LP), values=torch.stack(V), rewards=torch.stack(R),
                dones=torch.stack(D), valid=torch.stack(M)), fitness, simulated


def gae(rewards, values, dones, gamma, lam):
    """Advantages and returns; a done step does not bootstrap (the life ended there)."""
    T = rewards.shape[0]
    adv = torch.zeros_like(rewards)
    last = torch.zeros_like(rewards[0])
    for t in reversed(range(T)):
        nxt = values[t + 1] if t + 1 < T else torch.zeros_like(values[t])
        keep = (~dones[t]).float()
        delta = rewards[t] + gamma * nxt * keep - values[t]
        last = delta + gamma * lam * keep * last
        adv[t] = last
    return adv, adv + values


def update(agent, opt, data, args, gen):
    """Clipped-objective PPO epochs over the valid steps. Returns the last minibatch's
    losses (policy, value) as floats."""
    valid = data["valid"].reshape(-1)
    x = agent.normalise(data["raw"]).reshape(-1, *data["raw"].shape[2:])[valid]
    clock = data["clock"].reshape(-1, 3)[valid]
    actions = data["actions"].reshape(-1, data["actions"].shape[-1])[valid]
    old_logp = data["logp"].reshape(-1, data["logp"].shape[-1])[valid]
    rewards = data["rewards"] * args.reward_scale
    adv, ret = gae(rewards, data["values"], data["dones"], args.gamma, args.lam)
    adv, ret = adv.reshape(-1)[valid], ret.reshape(-1)[valid]
    adv = (adv - adv.mean()) / (adv.std() + 1e-8)
    count = x.shape[0]
    size = max(1, count // args.minibatches)
    losses = (float("nan"), float("nan"))
    for _ in range(args.epochs):
        order = torch.randperm(count, generator=gen)
        for start in range(0, count, size):
            idx = order[start:start + size]
            # The actor's loss on a random subset of the voxels (all share its weights, so
            # this is an unbiased estimate at a fraction of the cost); the critic sees all.
            vox = torch.randperm(x.shape[1], generator=gen)[:args.voxel_sample]
            mu = agent.mean(x[idx][:, vox])
            logp = torch.distributions.Normal(mu, torch.exp(agent.log_std)).log_prob(
                actions[idx][:, vox])
            ratio = torch.exp(logp - old_logp[idx][:, vox])  # per voxel
            a = adv[idx, None]
            policy_loss = -torch.min(ratio * a,
                                     ratio.clamp(1 - args.clip, 1 + args.clip) * a).mean()
            value_loss = 0.5 * ((agent.value(x[idx], clock[idx]) - ret[idx]) ** 2).mean()
            loss = policy_loss + args.value_coef * value_loss
            opt.zero_grad()
            loss.backward()
            nn.utils.clip_grad_norm_(agent.parameters(), args.max_grad_norm)
            opt.step()
            losses = (float(policy_loss), float(value_loss))
    return losses


def save_atomic(state, path):
    """torch.save to PATH.tmp, flushed to disk, then renamed over PATH: a kill leaves the old
    checkpoint or the new one, never a torn file."""
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        torch.save(state, f)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def parser():
    ap = argparse.ArgumentParser(prog="python3 -m plastivox.ppo",
                                 description=__doc__.split("\n\n")[0])
    ap.add_argument("--robot", help="robot file (default: the demo walker)")
    ap.add_argument("--task", default="walk")
    ap.add_argument("--treatment", help="override the robot's treatment (none: no development)")
    ap.add_argument("--duration", type=float, default=1.0, help="life, s")
    ap.add_argument("--settle-time", type=float, default=0.2)
    ap.add_argument("--every", type=int, default=10, help="engine steps an action is held")
    ap.add_argument("--num-envs", type=int, default=8)
    ap.add_argument("--threads", type=int, default=1, help="the environments' C++ threads")
    ap.add_argument("--torch-threads", type=int, default=1)
    ap.add_argument("--steps", type=int, default=2_000_000,
                    help="budget: engine steps of every life simulated, evaluations included")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--hidden", type=int, default=16)
    ap.add_argument("--lr", type=float, default=3e-4)
    ap.add_argument("--epochs", type=int, default=10)
    ap.add_argument("--minibatches", type=int, default=32)
    ap.add_argument("--clip", type=float, default=0.2)
    ap.add_argument("--gamma", type=float, default=0.99)
    ap.add_argument("--lam", type=float, default=0.95)
    ap.add_argument("--value-coef", type=float, default=0.5)
    ap.add_argument("--max-grad-norm", type=float, default=0.5)
    ap.add_argument("--voxel-sample", type=int, default=128,
                    help="voxels of each sample in the actor's loss (all if fewer)")
    ap.add_argument("--reward-scale", type=float, default=100.0)
    ap.add_argument("--eval-every", type=int, default=2, help="iterations between evaluations")
    ap.add_argument("--checkpoint", required=True, help="the run's state; resumed if present")
    ap.add_argument("--quiet", action="store_true")
    return ap


def robot_of(args):
    robot = plastivox.load_robot(args.robot) if args.robot else plastivox.demo_walker()
    return robot.with_physics({"duration": args.duration, "settle_time": args.settle_time},
                              **({"treatment": args.treatment} if args.treatment else {}))


# What must match for a checkpoint to be resumed: everything that changes the run's bits.
_IDENTITY = ["robot", "task", "treatment", "duration", "settle_time", "every", "num_envs",
             "steps", "seed", "hidden", "lr", "epochs", "minibatches", "clip", "gamma", "lam",
             "value_coef", "max_grad_norm", "reward_scale", "voxel_sample", "eval_every",
             "torch_threads"]


def train(args, stop_after=None):
    """Trains until args.steps engine steps have been simulated (or stop_after iterations in
    this call, for tests). Returns the checkpoint's state dict."""
    torch.set_num_threads(args.torch_threads)
    identity = {k: getattr(args, k) for k in _IDENTITY}
    robot = robot_of(args)
    vec = make_env(robot, args.task, args.num_envs, args.every, args.threads)
    probe = make_env(robot, args.task, 1, args.every, 1)  # the mean action's lives
    feat = Features(vec.single_env)
    torch.manual_seed(args.seed)
    agent = Agent(args.hidden)
    opt = torch.optim.Adam(agent.parameters(), lr=args.lr, eps=1e-5)
    gen = torch.Generator().manual_seed(args.seed)
    state = {"identity": identity, "iteration": 0, "steps": 0, "cpu_seconds": 0.0,
             "best": {"fitness": -math.inf, "steps": 0, "cpu_seconds": 0.0, "iteration": 0},
             "log": []}
    if os.path.exists(args.checkpoint):
        saved = torch.load(args.checkpoint)
        if saved["identity"] != identity:
            diff = next(k for k in _IDENTITY if saved["identity"].get(k) != identity[k])
            raise SystemExit(f"{args.checkpoint}: checkpoint of another run ({diff}: "
                             f"{saved['identity'].get(diff)!r} there, {identity[diff]!r} here)")
        agent.load_state_dict(saved["agent"])
        opt.load_state_dict(saved["optimizer"])
        gen.set_state(saved["generator"])
        state = {k: saved[k] for k in state}
        if not args.quiet:
            print(f"resuming after iteration {state['iteration']} ({state['steps']} steps)")
    start_cpu = time.process_time() - state["cpu_seconds"]
    done_here = 0
    while state["steps"] < args.steps and (stop_after is None or done_here < stop_after):
        data, fitness, steps = rollout(agent, vec, feat, gen)
        state["steps"] += steps
        losses = update(agent, opt, data, args, gen)
        agent.observe_stats(data["raw"][data["valid"]])
        state["iteration"] += 1
        done_here += 1
        entry = {"iteration": state["iteration"], "steps": state["steps"],
                 "train_fitness": float(fitness.mean()), "policy_loss": losses[0],
                 "value_loss": losses[1], "std": float(torch.exp(agent.log_std))}
        if state["iteration"] % args.eval_every == 0 or state["steps"] >= args.steps:
            life, best, steps = rollout(agent, probe, feat, gen, deterministic=True)
            state["steps"] += steps
            entry["eval_fitness"] = float(best[0])
            if best[0] > state["best"]["fitness"]:
                # The actions as sent (float64, clipped), so replay() can run the life again.
                sent = life["actions"][:, 0].double().clamp(-1, 1)
                state["best"] = {"fitness": float(best[0]), "steps": state["steps"],
                                 "cpu_seconds": time.process_time() - start_cpu,
                                 "iteration": state["iteration"], "actions": sent}
        state["cpu_seconds"] = time.process_time() - start_cpu
        entry["cpu_seconds"] = state["cpu_seconds"]
        state["log"].append(entry)
        save_atomic(dict(state, agent=agent.state_dict(), optimizer=opt.state_dict(),
                         generator=gen.get_state()), args.checkpoint)
        if not args.quiet:
            print(f"iter {entry['iteration']:4d}  steps {entry['steps']:9d}  "
                  f"cpu {entry['cpu_seconds']:7.1f} s  train {entry['train_fitness']:8.4f}  "
                  f"eval {entry.get('eval_fitness', float('nan')):8.4f}  "
                  f"best {state['best']['fitness']:8.4f}  std {entry['std']:.3f}  "
                  f"loss {losses[0]:+.4f} {losses[1]:.4f}", flush=True)
    return dict(state, agent=agent.state_dict())


def replay(args, actions):
    """The life of a sequence of actions (one row of the robot's voxels per call, each held
    args.every steps, as the environments hold them), run again in a Simulator: its Result,
    which simulate() would give that life (fitness and `success` by the task's criterion).
    replay(args, state["best"]["actions"]) is the champion's life, bit for bit."""
    robot = robot_of(args).with_physics(task=args.task)
    sim = plastivox.Simulator(robot)
    for row in np.asarray(actions, dtype=np.float64):
        if sim.status != "running":
            break
        sim.set_actuation(row)
        sim.step(args.every)
    return sim.result()


def main(argv=None):
    args = parser().parse_args(argv)
    for name in ("num_envs", "every", "torch_threads", "steps", "eval_every", "epochs",
                 "minibatches", "hidden", "voxel_sample"):
        if getattr(args, name) < 1:
            raise SystemExit(f"--{name.replace('_', '-')}: must be >= 1, got {getattr(args, name)}")
    state = train(args)
    best = {k: v for k, v in state["best"].items() if k != "actions"}
    print(json.dumps({"method": "ppo", "seed": args.seed, "steps": state["steps"],
                      "cpu_seconds": round(state["cpu_seconds"], 2), "best": best}))


if __name__ == "__main__":
    main()
