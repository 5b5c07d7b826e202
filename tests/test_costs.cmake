# COST of the longest GoogleTest cases, included by CTest after the discovered tests
# (TEST_INCLUDE_FILES, tests/CMakeLists.txt; the CTest tests added there by add_test get theirs
# beside it). Under `ctest -j2` CTest starts tests in decreasing COST until a run in the build
# directory has recorded real times (Testing/Temporary/CTestCostData.txt), as in CI's fresh clone, so
# the longest no longer start last. Values: seconds of one `ctest -j2` run on 2 cores (its
# LastTest.log), rounded; only their order matters, and a renamed case just loses its place. A name
# missing here is ignored by set_tests_properties.
foreach(entry
    "ReproduceCommand.PlotsRunBesideAndEachMarkerHoldsItsOwnOutputs;7"
    "ReproduceCommand.QuickFitStepWritesIntoResultsQuick;6"
    "ShaderExport.EveryMethodCompilesRunsAndMatchesTheReference;6"
    "ReproduceCommand.ToolsRunFromTheRepositoryRootLeavePaperTablesAlone;5.5"
    "VmfEm.FitsTheFinestLevelWithinItsCostGuard;2.5"
    "HardeningExtremes.GroupK_GrazingMirrorReferences;4.5"
    "HardeningExtremes.GroupL_AsgSgProductBothSharp;4.5"
    "ReproduceCommand.QuickRenderSweepStepWritesIntoResultsQuick;4"
    "SparseEnvMap.ResolvedSunImprovesOnTheUnresolvedFit;3"
    "EvalCommand.EveryRegisteredMethodEvaluatesInEveryPrecision;4"
    "SgFree.SunSizedFeatureImprovesOnTheOneLobeFloor;3"
    "Reference.DoubleAgreesWithFiftyDigitsOverTheWholeRange;3"
    "NearWallLibrary.ReferenceAgainstQuadratureAndSmapeFromThePixels;3"
    "GaussianNdfReference.MatchesAnIndependentHalfVectorQuadrature;2.5"
    "Reference.AgreesWithBesselThetaForm;2"
    "GaussianNdfCommand.SweepWithTheGaussianBrdfWritesItsOwnTable;2"
    "ParserFuzz.ConstantSetReaderFailsOnlyWithShortUsageErrors;2"
    "FitReal.EveryObjectiveReproducesTheCommittedConstants;2"
    "SgLobeSimilarity.Mp50ExactFormMatchesMp50Quadrature;1.7")
  list(GET entry 0 test_name)
  list(GET entry 1 test_cost)
  set_tests_properties("${test_name}" PROPERTIES COST ${test_cost})
endforeach()
