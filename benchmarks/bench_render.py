"""Render benchmark: ``python benchmarks/bench_render.py`` is ``aquagait bench render``.

Milliseconds per 640x480 picture of the fish among 3,000 particle traces of
15 positions (OpenGL through EGL on Mesa's llvmpipe), with llvmpipe's own
threads and on one (target, issue 14: at most 100 ms on one core); then whole
1280x720 pictures of a one-second fish swim as ``aquagait swim`` draws them,
with the wake's vortex surfaces and traces, each alone and both (target,
issue 33: at most 150 ms a picture on one core); each beside the time to
encode the same pictures into an MP4 in the same run.
"""

import argparse

from aquagait.bench import run_benchmark

if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=30, help="pictures timed per case")
    run_benchmark("render", repeats=parser.parse_args().repeats)
