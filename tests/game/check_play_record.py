#!/usr/bin/env python3
"""Checks what `penumbra_play --bench` wrote (tests/game/CMakeLists.txt): the GPU-timed frames
and the measured frames are the frames after the warm-up, apart; the empty-frame baseline has
both halves."""
import json
import sys

r = json.load(open(sys.argv[1]))
run, frame = r["run"], r["frame"]
errors = []
if run["gpu_timed_frames"] < 1:
    errors.append(f"no GPU-timed frames: {run['gpu_timed_frames']}")
if run["timed_frames"] + run["gpu_timed_frames"] != run["frames"] - run["warmup"]:
    errors.append(f"measured {run['timed_frames']} + GPU-timed {run['gpu_timed_frames']} != "
                  f"{run['frames']} frames - {run['warmup']} warm-up")
for key in ("empty_frame_before_ms", "empty_frame_after_ms", "empty_frame_ms"):
    if not frame[key] > 0:
        errors.append(f"{key} = {frame[key]}")
if not r["gpu_pass_ms"]:
    errors.append("no GPU pass times")
print("\n".join(errors) or "record ok")
sys.exit(1 if errors else 0)
