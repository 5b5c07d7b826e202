# COST of the longest GoogleTest cases, included by CTest after the discovered tests
# (TEST_INCLUDE_FILES, tests/CMakeLists.txt; the CTest tests added there by add_test get theirs
# beside it). Under `ctest -j2` CTest starts tests in decreasing COST until a run in the build
# directory has recorded real times (Testing/Temporary/CTestCostData.txt), as in CI's fresh clone, so
# the longest no longer start last. Values: seconds of one `ctest -j2` run on 2 cores (its
# LastTest.log), rounded; only their order matters, and a renamed case just loses its place. A name
# missing here is ignored by set_tests_properties.
foreach(entry
    "ReproduceCommand.QuickFitStepWritesIntoResultsQuick;6"
    "ShaderExport.EveryMethodCompilesRunsAndMatchesTheReference;6"
    "ReproduceCommand.ToolsRunFromTheRepositoryRootLeavePaperTablesAlone;5.5"
    "VmfEm.FitsTheFinestLevelWithinItsCostGuard;1.7"
    "ReproduceCommand.QuickRenderSweepStepWritesIntoResultsQuick;4"
    "SparseEnvMap.ResolvedSunImprovesOnTheUnresolvedFit;3"
    "EvalCommand.EveryRegisteredMethodEvaluatesInEveryPrecision;3.5"
    "SgFree.SunSizedFeatureImprovesOnTheOneLobeFloor;2.7"
    "ReproduceCommand.PlotsRunBesideAndEachMarkerHoldsItsOwnOutputs;3"
    "GaussianNdfCommand.SweepWithTheGaussianBrdfWritesItsOwnTable;2"
    "HardeningExtremes.GroupL_AsgSgProductBothSharp;1.4"
    "ParserFuzz.ConstantSetReaderFailsOnlyWithShortUsageErrors;2"
    "FitReal.EveryObjectiveReproducesTheCommittedConstants;2"
    "HardeningExtremes.GroupK_GrazingMirrorReferences;1.2"
    "GaussianNdfReference.MatchesAnIndependentHalfVectorQuadrature;1.2")
  list(GET entry 0 test_name)
  list(GET entry 1 test_cost)
  set_tests_properties("${test_name}" PROPERTIES COST ${test_cost})
endforeach()
