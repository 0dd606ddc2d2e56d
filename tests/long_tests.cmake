# The tests of weft_tests and weft_allocation_tests that take 4 s or more in release on 2 cores
# are labelled long, the others quick, so that `ctest --preset release -L quick` (about a minute)
# is an edit-and-test loop; scripts/test and CI run them all. ctest includes this file after the
# discovered tests, whose names the discovery left in weft_tests_TESTS and
# weft_allocation_tests_TESTS.
set(long_tests
  EnergyBudget.TheTwistClosesThroughItsRope
  EnergyBudget.EveryShippedSceneClosesWithinOnePercent
  TierGates.TheShippedDrapeSettingsPassEveryGate
  TierGates.CandidatesThatShouldFailDo
  TierGates.TheFastTierPassesEveryGate
  BarrierResponse.ImpactAt20MetresASecondNeedsNoStrainLimit
  Untangling.EveryTangledSceneIsCleanFromTheFirstFrameOn
  Untangling.WorksWithTheBarrierResponseToo
  CheckpointResume.KilledRunResumesBitIdentically
  HangingCloth.SwingsDownAndComesToRestWithPinsFixed
  CollisionScenes.FiveTurnTwistStaysCleanAndReportsEveryEdgeOverTheStrainLimit
  CollisionScenes.DrapeWithASmallestStretchConvergesWhereWingsCollapsed
  CollisionScenes.FastImpactOnThinBoxesStaysWithinTheStrainLimit
  StiffCloth.FortyByFortyWithFiveNewtonIterationsAStepStaysBoundedAndSettles
  SteadyStateTumble.TumbleDryerStepsAllocateNothing
  SteadyStateSwitch.StepsThatPutTheHingesBackIntoTheMatrixAllocateNothing
  BadInput.SceneTooLargeForMemoryIsRefused
)
foreach(discovered IN LISTS weft_tests_TESTS weft_allocation_tests_TESTS)
  list(FIND long_tests "${discovered}" position)
  if(position EQUAL -1)
    set_tests_properties("${discovered}" PROPERTIES LABELS quick)
  else()
    set_tests_properties("${discovered}" PROPERTIES LABELS long)
  endif()
endforeach()
