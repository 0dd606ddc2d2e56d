# Tests of weft_tests left out of the sanitizer suite (the asan test preset excludes this label;
# docs/hardening.md). Each takes minutes under ASan and UBSan at
# -O1, where the whole rest of the suite takes about ten; shorter tests run the same code there,
# and the release suite runs these. ctest includes this file after the discovered tests;
# slurm_sweep is labelled in tests/CMakeLists.txt.
set_tests_properties(
  # 7 min: kills runs at many points; the four other CheckpointResume tests resume under ASan.
  CheckpointResume.KilledRunResumesBitIdentically
  # over 5 min: a long settle of a hanging cloth; StiffCloth.ImplicitEuler* and the integrator
  # tests step the same terms. (The 100x100 stiff cloth is in weft_large_tests, label large.)
  HangingCloth.SwingsDownAndComesToRestWithPinsFixed
  # 2-2.5 min: every shipped scene's energy budget; the other EnergyBudget tests run its code.
  EnergyBudget.EveryShippedSceneClosesWithinOnePercent
  # ~2 min in release: 90 frames of the twist at 32x16, up to 200 Newton iterations a step.
  EnergyBudget.TheTwistClosesThroughItsRope
  # 2 min: a long adaptive run; the other AdaptiveStepping tests run its code.
  AdaptiveStepping.StiffUndampedSpringsStayNearTheReferenceAndCreateNoEnergy
  # 2 min each: full-length collision scenes; the shorter CollisionScenes tests (twist, soft
  # balls, tumble dryer, drape) run the same collision phase.
  CollisionScenes.FiveTurnTwistStaysCleanAndReportsEveryEdgeOverTheStrainLimit
  CollisionScenes.FastImpactOnThinBoxesStaysWithinTheStrainLimit
  # ~1 min each in release: the 64x64 drape in two or three settings (and three hanging cloths
  # settled for 6 s); the CollisionScenes and EnergyBudget tests run the same phases on the drape.
  TierGates.TheShippedDrapeSettingsPassEveryGate
  TierGates.TheFastTierPassesEveryGate
  TierGates.CandidatesThatShouldFailDo
  # ~20 s in release: four 20 m/s impacts with the barrier response, up to 600 Newton iterations
  # a step; BarrierResponse.DrapeStaysCleanConvergedAndBudgeted runs the same code.
  BarrierResponse.ImpactAt20MetresASecondNeedsNoStrainLimit
  PROPERTIES LABELS not_under_asan)
