# Shared by scripts/fuzz.sh, fuzz_explore.sh and fuzz_build.sh: the harnesses and the limits.
HARNESSES=(fuzz_scene_obj fuzz_scene_ply fuzz_scene_gltf fuzz_scene_glb fuzz_vdb)
# A single allocation above this fails the input (deterministic, unlike an RSS limit, which
# libFuzzer samples once a second). Scene loaders promise max(256 MB, 64 x file size)
# (docs/scene.md, "Memory bound"); fuzz inputs are a few KB, so 256 MB is that bound.
MALLOC_LIMIT_MB=256
# Peak resident memory: a safety net for runaway growth made of many small allocations.
RSS_LIMIT_MB=2048
