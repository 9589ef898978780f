#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Explores disc-kernel constructions beyond the library's tables (docs/disc-kernel.md, "Longer
chains and other constructions"): longer chains, rows and columns with different chains, a final
shared real (heat) step, fits at one CoC or all, the ring bound. Same discrete-resolvent model and
metric as fit_disc_kernel.py (it imports it); prints SNR at d = 12/32/80, energy, most negative
value, and the error split into its radial part and the non-radial residual (the cross).

    python3 study/lens/disc_study.py --C 2 --M 4 [--asym] [--heat] [--ring 0.11] [--mix 3]
        [--diameters 12 32 80] [--weights 1 1 1] [--trials N] [--seconds S] [--init FILE]
        [--save FILE]

--table FIT.json ...: the table of docs/disc-kernel.md from saved fits (study/lens/disc_study_fits/).
--gaussians: exact complex Gaussians (C = 2, 3) fitted at each d, for comparison.
Also --bounds: the best any separable C-component kernel can do (Re sum_c mix_c g_c(x) g_c(y)
is a symmetric matrix with at most C positive and C negative eigenvalues: keep the disc's largest
ones).
"""
import argparse
import json
import sys
import time

import numpy as np
from scipy.optimize import least_squares

sys.path.insert(0, __file__.rsplit("/", 1)[0])
import fit_disc_kernel as fdk  # noqa: E402


class Model:
    """C components; per component a row chain of M steps and (asym) a column chain of M
    steps; (heat) one shared real step of beta = h d^2 on both axes after the sum."""

    def __init__(self, C, M, asym=False, heat=False, zeros=0):
        self.C, self.M, self.asym, self.heat, self.zeros = C, M, asym, heat, zeros
        self.phase_max = 1.0  # |arg kappa| < phase_max pi / 2 (1: Re kappa > 0, stable)
        self.nk = C * M * (2 if asym else 1)
        self.n = 2 * self.nk + 2 * (C - 1) + 1 + (1 if heat else 0) + 2 * C * zeros

    def unpack(self, p):
        C, M = self.C, self.M
        k = np.exp(p[0:2 * self.nk:2]) * np.exp(1j * (np.pi / 2) * self.phase_max *
                                                 np.tanh(p[1:2 * self.nk:2]))
        rows = k[:C * M].reshape(C, M)
        cols = k[C * M:].reshape(C, M) if self.asym else rows
        q = 2 * self.nk
        mix = np.zeros(C, complex)
        for c in range(C - 1):
            mix[c] = p[q] + 1j * p[q + 1]
            q += 2
        mix[C - 1] = (1 - mix[:C - 1].real.sum()) + 1j * p[q]
        q += 1
        h = np.exp(p[q]) if self.heat else 0.0
        q += 1 if self.heat else 0
        z = p[q:q + 2 * self.C * self.zeros]
        self.alpha = (np.exp(z[0::2]) * np.exp(1j * z[1::2])).reshape(self.C, self.zeros)
        return rows, cols, mix, h

    def cost(self):
        """Complex line solves per pixel per axis (a real one counted as 1/2)."""
        return self.C * self.M + (0.5 if self.heat else 0.0)


def chain_half(kappas, d, half, h=0.0, alphas=()):
    """The chain's 1-D kernel on [0, half] (it is even). alphas: explicit steps
    y = x + alpha d^2 (x_{i-1} - 2 x_i + x_{i+1}) (3 taps, no solve)."""
    ks = list(kappas) + ([h] if h else [])
    g = None
    for kap in ks:
        r = fdk.resolvent(kap * d * d, 2 * half)
        g = r if g is None else np.convolve(g, r, mode="same")
    for a in alphas:
        b = a * d * d
        g = np.convolve(g, np.array([b, 1 - 2 * b, b]), mode="same")
    return g[2 * half:3 * half + 1] if len(ks) else None


def chain_full(kappas, d, half, h=0.0):
    g = chain_half(kappas, d, half, h)
    return np.concatenate([g[:0:-1], g])


def kernel_quadrant(model, p, d, half):
    rows, cols, mix, h = model.unpack(p)
    K = 0
    for c in range(model.C):
        al = model.alpha[c] if model.zeros else ()
        gr = chain_half(rows[c], d, half, h, al)
        gc = chain_half(cols[c], d, half, h, al) if model.asym else gr
        K = K + mix[c] * np.outer(gc, gr)
    return K.real


def kernel_full(model, p, d, half):
    Q = kernel_quadrant(model, p, d, half)
    top = np.concatenate([Q[:0:-1], Q], axis=0)
    return np.concatenate([top[:, :0:-1], top], axis=1)


def radial_split(K, D):
    """|K - D|^2 = |P(K - D)|^2 + |(I - P)(K - D)|^2, P the average over pixels of equal x^2 + y^2
    (an orthogonal projection onto radial functions). Returns the SNRs of each part alone and
    the disc's own non-radial part."""
    n = K.shape[0]
    c = n // 2
    y, x = np.mgrid[-c:c + 1, -c:c + 1]
    r2 = (x * x + y * y).ravel()
    _, inv, cnt = np.unique(r2, return_inverse=True, return_counts=True)

    def P(A):
        s = np.bincount(inv, A.ravel()) / cnt
        return s[inv].reshape(A.shape)

    E = K - D
    nD = np.linalg.norm(D)
    rad = np.linalg.norm(P(E))
    non = np.linalg.norm(E - P(E))
    return (-20 * np.log10(rad / nD), -20 * np.log10(non / nD),
            -20 * np.log10(np.linalg.norm(D - P(D)) / nD))


def measure(model, p, d, half=None):
    half = half if half is not None else int(d) + 3
    D = fdk.disc(d, half)
    K = kernel_full(model, p, d, half)
    snr = -20 * np.log10(np.linalg.norm(K - D) / np.linalg.norm(D))
    return dict(snr=snr, ring=K.min() / D.max(), over=K.max() / D.max() - 1, energy=K.sum(),
                split=radial_split(K, D))


def fit(model, diameters, weights, ring, mix_bound, trials, seconds, rng, inits=(),
        max_nfev=300, ring_weight=3.0):
    data = []
    for d, wgt in zip(diameters, weights):
        half = int(d) + 3
        D = fdk.disc(d, half)
        Q = D[half:, half:]
        m = np.where(np.arange(half + 1) == 0, 1.0, 2.0)
        W = np.sqrt(np.outer(m, m))  # each quadrant pixel stands for its mirror images
        data.append((d, half, Q, W, np.sqrt(wgt) / np.linalg.norm(D), D.max()))

    def residual(p):
        out = []
        for d, half, Q, W, s, hmax in data:
            K = kernel_quadrant(model, p, d, half)
            out.append(((K - Q) * W * s).ravel())
            out.append((ring_weight * W * np.minimum(K / hmax + ring, 0)).ravel())
        _, _, mix, _ = model.unpack(p)
        out.append(np.maximum(np.abs(mix) - mix_bound, 0))
        return np.concatenate(out)

    best = None
    start = time.time()
    starts = [np.asarray(x, float) for x in inits]
    t = 0
    while (t < trials or starts) and time.time() - start < seconds:
        if starts:
            p0 = starts.pop(0)
        else:
            p0 = rng.normal(0, 1, model.n)
            for i in range(model.nk):
                p0[2 * i] = np.log(0.03 / model.M) + rng.normal(0, 1)
                p0[2 * i + 1] = rng.normal(0, 1.5)
            if model.heat:
                p0[2 * model.nk + 2 * (model.C - 1) + 1] = np.log(0.002) + rng.normal(0, 1)
            if model.zeros:
                p0[model.n - 2 * model.C * model.zeros::2] = np.log(0.003) + rng.normal(
                    0, 1, model.C * model.zeros)
            t += 1
        r = least_squares(residual, p0, max_nfev=max_nfev)
        if best is None or r.cost < best.cost:
            best = r
            print("  trial %d (%.0f s): cost %.5g: %s" % (t, time.time() - start, r.cost, ", ".join(
                "d=%d %.2f dB ring %.3f" % (d, m["snr"], m["ring"])
                for d in (12, 32, 80) for m in [measure(model, r.x, d)])),
                file=sys.stderr, flush=True)
    return best.x


def extend(model_from, p, model_to, rng):
    """Starting points for a longer chain (or asym / heat) from a fitted shorter one: the new
    steps start small and in the middle of the existing ones' phases."""
    rows, cols, mix, h = model_from.unpack(p)
    C, M = model_to.C, model_to.M
    starts = []
    for variant in range(3):
        q = []
        for chains in ([rows] + ([cols if model_from.asym else rows] if model_to.asym else [])):
            for c in range(C):
                ks = list(chains[c]) if c < model_from.C else []
                while len(ks) < M:
                    if ks and variant == 0:
                        ks.append(min(ks, key=abs) * 0.05)
                    elif ks and variant == 1:
                        big = max(range(len(ks)), key=lambda i: abs(ks[i]))
                        ks[big] *= 0.5
                        ks.append(ks[big])
                    else:
                        ks.append(0.003 * np.exp(1j * rng.uniform(-1.4, 1.4)))
                for k in ks[:M]:
                    ph = np.clip(np.angle(k) / (np.pi / 2) / model_to.phase_max, -0.999999,
                                 0.999999)
                    q += [np.log(abs(k)), np.arctanh(ph)]
        for c in range(C - 1):
            m = mix[c] if c < model_from.C - 1 else 0.0
            q += [m.real, m.imag]
        q.append(mix[min(C, model_from.C) - 1].imag)
        if model_to.heat:
            q.append(np.log(h) if h else np.log(0.001))
        for c in range(C):
            for z in range(model_to.zeros):
                q += [np.log(1e-4), rng.uniform(-3, 3)]
        starts.append(np.array(q))
    return starts


def bounds():
    for d in (12, 32, 80):
        D = fdk.disc(d, d + 3)
        w = np.linalg.eigvalsh(D)
        pos, neg = np.sort(w[w > 0])[::-1], np.sort(-w[w < 0])[::-1]
        n2 = np.sum(w * w)
        print("d=%d: " % d + ", ".join(
            "C=%d %.2f dB" % (C, -10 * np.log10(1 - (np.sum(pos[:C] ** 2) + np.sum(neg[:C] ** 2))
                                                   / n2)) for C in (1, 2, 3, 4)))


def gaussians(trials=30, seed=3):
    """Re sum_c mix_c exp(-(a_c + i b_c) (x^2 + y^2) / d^2) sampled at pixel centres, fitted at
    each d alone (the construction the chains approximate)."""
    rng = np.random.default_rng(seed)
    for C in (2, 3):
        for d in (12, 32, 80):
            half = d + 3
            D = fdk.disc(d, half)
            x = np.arange(-half, half + 1) / d

            def K(p):
                k = 0
                for c in range(C):
                    g = np.exp(-(np.exp(p[2 * c]) + 1j * p[2 * c + 1]) * x * x)
                    k = k + (p[2 * C + 2 * c] + 1j * p[2 * C + 2 * c + 1]) * np.outer(g, g)
                return k.real / k.real.sum()

            def res(p):
                return ((K(p) - D) / np.linalg.norm(D)).ravel()

            best = None
            for _ in range(trials):
                p0 = np.concatenate([np.stack([np.log(rng.uniform(0.5, 8, C)),
                                               rng.normal(0, 8, C)], 1).ravel(),
                                     rng.normal(0, 1, 2 * C)])
                r = least_squares(res, p0, max_nfev=400)
                best = r if best is None or r.cost < best.cost else best
            k = K(best.x)
            print("C=%d d=%d complex Gaussians: %.2f dB, most negative %.3f" % (
                C, d, -20 * np.log10(np.linalg.norm(k - D) / np.linalg.norm(D)),
                k.min() / D.max()), flush=True)


def report(model, p, label):
    rows = []
    for d in (12, 32, 80):
        m = measure(model, p, d)
        mt = measure(model, p, d, ((3 * d + 9) | 1) // 2)  # the test's window
        rows.append((d, m, mt))
        print("%s d=%d: %.2f dB (test window %.2f), ring %.3f, over %.3f, energy %.5f, "
              "radial-only %.2f dB, non-radial-only %.2f dB (disc's own %.1f)" % (
                  label, d, m["snr"], mt["snr"], m["ring"], m["over"], m["energy"],
                  *m["split"]))
    return rows


def describe(s):
    """A fit's construction in words, from its saved file."""
    words = ["%d x %d" % (s["C"], s["M"])]
    if s["asym"]:
        words.append("rows and columns with their own chains")
    if s["heat"]:
        words.append("+ one shared real step")
    if s.get("zeros"):
        words.append("+ %d explicit step%s per chain" % (s["zeros"], "s" [:s["zeros"] > 1]))
    if s.get("phase_max", 1.0) != 1.0:
        words.append("arg kappa up to %.0f deg (Re kappa < 0: unstable, reference only)"
                     % (90 * s["phase_max"]))
    if s["mix"] != fdk.MIX_BOUND:
        words.append("abs(mix) <= %g" % s["mix"])
    if s["ring"] >= 1:
        words.append("no ring bound")
    elif s["ring"] != fdk.RING:
        words.append("rings >= -%g%%" % (100 * s["ring"]))
    if list(s["diameters"]) != [12, 32, 80]:
        words.append("fitted at d = %s only" % ", ".join("%g" % d for d in s["diameters"]))
    return ", ".join(words)


def table(files):
    """The markdown table of docs/disc-kernel.md from saved fits."""
    print("| construction | complex steps per axis | CoC 12 | CoC 32 | CoC 80 | most negative "
          "| overshoot | energy | non-radial part alone (CoC 80) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for fn in files:
        s = json.load(open(fn))
        m = Model(s["C"], s["M"], s["asym"], s["heat"], s.get("zeros", 0))
        m.phase_max = s.get("phase_max", 1.0)
        p = np.array(s["p"])
        ms = {d: measure(m, p, d) for d in (12, 32, 80)}
        mt = {d: measure(m, p, d, ((3 * d + 9) | 1) // 2) for d in (12, 32, 80)}
        cost = "%g" % m.cost() + (" + %d explicit" % (m.zeros * m.C) if m.zeros else "")
        energy = max((mt[d]["energy"] for d in mt), key=lambda e: abs(e - 1))
        print("| %s | %s | %.2f | %.2f | %.2f | %.1f%% | %.0f%% | %.4f | %.1f dB |" % (
            s.get("label") or describe(s), cost, ms[12]["snr"], ms[32]["snr"], ms[80]["snr"],
            100 * min(ms[d]["ring"] for d in ms), 100 * max(ms[d]["over"] for d in ms),
            energy, ms[80]["split"][1]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--C", type=int, default=2)
    ap.add_argument("--M", type=int, default=2)
    ap.add_argument("--asym", action="store_true")
    ap.add_argument("--heat", action="store_true")
    ap.add_argument("--phase-max", type=float, default=1.0,
                    help="allow |arg kappa| up to this times pi/2 (> 1: Re kappa < 0, unstable;"
                    " for measuring what the stability bound costs)")
    ap.add_argument("--zeros", type=int, default=0, help="explicit steps per chain")
    ap.add_argument("--ring", type=float, default=fdk.RING)
    ap.add_argument("--mix", type=float, default=fdk.MIX_BOUND)
    ap.add_argument("--diameters", type=float, nargs="+", default=[12, 32, 80])
    ap.add_argument("--weights", type=float, nargs="+")
    ap.add_argument("--trials", type=int, default=6)
    ap.add_argument("--seconds", type=float, default=300)
    ap.add_argument("--nfev", type=int, default=300)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--init", nargs="*", default=[], help="saved fits to start from")
    ap.add_argument("--save")
    ap.add_argument("--bounds", action="store_true")
    ap.add_argument("--gaussians", action="store_true",
                    help="fit exact complex Gaussians (C = 2, 3) at each d alone")
    ap.add_argument("--table", nargs="+", metavar="FIT.json",
                    help="print the docs' table of these saved fits")
    a = ap.parse_args()
    if a.bounds:
        bounds()
        return
    if a.gaussians:
        gaussians()
        return
    if a.table:
        table(a.table)
        return
    rng = np.random.default_rng(a.seed)
    model = Model(a.C, a.M, a.asym, a.heat, a.zeros)
    model.phase_max = a.phase_max
    inits = []
    for fn in a.init:
        s = json.load(open(fn))
        mf = Model(s["C"], s["M"], s["asym"], s["heat"], s.get("zeros", 0))
        mf.phase_max = s.get("phase_max", 1.0)
        if (mf.C, mf.M, mf.asym, mf.heat, mf.zeros, mf.phase_max) == (
                model.C, model.M, model.asym, model.heat, model.zeros, model.phase_max):
            inits.append(np.array(s["p"]))
        else:
            inits += extend(mf, np.array(s["p"]), model, rng)
    weights = a.weights or [1.0] * len(a.diameters)
    t0 = time.time()
    p = fit(model, a.diameters, weights, a.ring, a.mix, a.trials, a.seconds, rng, inits,
            a.nfev)
    label = "%dx%d%s%s%s" % (a.C, a.M, " asym" if a.asym else "", " +heat" if a.heat else "",
                             " +%d explicit" % a.zeros if a.zeros else "")
    rows = report(model, p, label)
    rows_, cols, mix, h = model.unpack(p)
    print("%s: cost %.1f complex steps per axis, fit %.0f s, |mix| max %.2f, kappa %s, mix %s, "
          "heat %.3g, explicit %s" % (label, model.cost(), time.time() - t0, np.abs(mix).max(),
                         np.round(rows_, 6).tolist(), np.round(mix, 4).tolist(), h,
                         np.round(model.alpha, 6).tolist() if a.zeros else []))
    if a.save:
        json.dump(dict(C=a.C, M=a.M, asym=a.asym, heat=a.heat, zeros=a.zeros, phase_max=a.phase_max, ring=a.ring, mix=a.mix,
                       diameters=a.diameters, weights=weights, p=list(p),
                       results={str(d): dict(snr=m["snr"], snr_test=mt["snr"], ring=m["ring"],
                                             energy=m["energy"], radial=m["split"][0],
                                             nonradial=m["split"][1]) for d, m, mt in rows}),
                  open(a.save, "w"), indent=1)


if __name__ == "__main__":
    main()
