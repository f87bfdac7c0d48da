"""Rates with their counts and 95 % Wilson score intervals, shared by the bench scripts
(bench/classify/evaluate.py, bench/classify/realcal.py, bench/sensordir/tabulate.py), and the
exact (Garwood) interval of a Poisson count (bench/classify/realcal.py, learned.py).
A script in bench/<name>/ imports it after sys.path.insert(0, <its folder>/..)."""
import math


def wilson(k, n, z=1.96):
    """The Wilson score interval (lo, hi) of k successes in n trials; (nan, nan) when n is 0."""
    if n == 0:
        return (float("nan"), float("nan"))
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return (max(0.0, c - h), min(1.0, c + h))


def rate(k, n):
    """'k/n = p% [lo, hi]' in percent with one decimal; 'k/0' when n is 0."""
    lo, hi = wilson(k, n)
    return f"{k}/{n} = {100 * k / n:.1f}% [{100 * lo:.1f}, {100 * hi:.1f}]" if n else f"{k}/0"


def poisson_exact(k):
    """95% exact (Garwood) interval of a Poisson count, by bisection on the cumulative sums."""
    def cdf(k, m):
        t = s = math.exp(-m)
        for i in range(1, k + 1):
            t *= m / i
            s += t
        return s
    def solve(f, lo, hi):
        for _ in range(200):
            mid = (lo + hi) / 2
            lo, hi = (mid, hi) if f(mid) else (lo, mid)
        return (lo + hi) / 2
    lo = 0.0 if k == 0 else solve(lambda m: 1 - cdf(k - 1, m) < 0.025, 0, 10 * k + 10)
    hi = solve(lambda m: cdf(k, m) > 0.025, 0, 10 * k + 20)
    return lo, hi
