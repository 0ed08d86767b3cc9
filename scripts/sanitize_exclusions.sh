# Sourced by scripts/test_sanitize.sh and scripts/test.sh: the tests that the ASan+UBSan suite
# leaves out. `scripts/test.sh --full` (CI) runs every test once: these in the Release suite,
# all the others under ASan+UBSan, so that CI stays within its 40 min on 2 cores (it had reached
# 2 544 s running the whole Release suite and then nearly all of it again under ASan).
#
# By label: slurm_cluster_test (`cluster`: Slurm daemons and whole bakes through them, code
# that the CLI tiles and slurm tests run under ASan at smaller sizes); install_example_test
# (`install`: links an example without sanitizer flags); quickstart_long_path_test
# (`quickstart`: the quick start's default bake); web_page_test (`web`: drives Chromium).
SANITIZE_SKIP_LABELS="cluster|install|quickstart|web"
# By name: the accuracy tests at default sizes (white furnaces, comparisons with the reference,
# photon tile merges at scale) and Blender's importers (200 test-seconds under ASan, issue 29's
# session), and four tests that compare whole files bit for bit (library vs CLI, one vs two
# threads, photon tile merges through the CLI and with depth: 86 test-seconds, issue 30's
# session). The same sampling, merge and export code runs under ASan in smaller tests. And four
# staged tile bakes of cli_tiles_test (53 test-seconds under ASan in issue 33's fourth session,
# when CI came within ~100 s of its 40 min; the other CliTiles tests, the tile-without-nodes
# merge among them, still run under ASan).
# And the tests that skip themselves under ASan (GTEST_SKIP under VDBLIGHT_SANITIZED: memory
# limits and peak RSS, which ASan's shadow memory swamps): run there, they would never run in CI.
# scripts/check_sanitize_exclusions.py (ctest: sanitize_exclusions) fails if one is missing here.
SANITIZE_SKIP_TESTS="^(BlenderFormats|BlenderPreview|PhotonReference|PhotonTiles|PhotonTilesDepth)\.\
|^(CliQueryStream\.LargerThanItsMemoryLimit|CliQueryStream\.StopsWithOneLineAtItsMemoryLimit\
|TileMemory\.ATileOfTheDefaultBakeHoldsAFractionOfTheWholeVolume)$\
|^(PhotonPass\.WhiteFurnaceAtDefaultBounces|Bake\.DefaultSceneAgainstReference\
|DirectBake\.OcclusionAndRuntimeMatchReferenceNearTheLuminaire|Transport\.ProbePassesKeepTheFurnace\
|Transport\.ClosedFurnaceBakeAtDefaults|BakeVolume\.LibraryAndCommandLineWriteIdenticalFiles\
|CliTiles\.PhotonBakesMergeToTheSingleBake|CliReproducible\.OneAndTwoThreadsGiveIdenticalFilesForEveryPass\
|CliTiles\.DefaultBakeTiledInStagesMergesToTheSingleBake|CliTiles\.SurfaceProbeCacheTiledInStagesMergesToTheSingleBake\
|CliTiles\.BadSetsOfPhotonTilesAreRefusedByName|CliTiles\.ErrorTargetedBakeWithTwoProbePassesMergesToTheSingleBake)$"
# The test programs that hold the tests above: in --full, the Release tree builds only these
# (and the CLI and benchmarks), not the ~100 others that run under ASan only.
# scripts/check_sanitize_exclusions.py fails if a test above lives in a program not listed here.
SANITIZE_SKIP_TARGETS="bake_test bake_volume_test blender_preview_test cli_query_stream_test cli_reproducible_test \
cli_tiles_test direct_bake_test photon_tiles_depth_test photon_tiles_test photons_accuracy_test photons_test \
scene_formats_test tile_memory_test transport_test"
