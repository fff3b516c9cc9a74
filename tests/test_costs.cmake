# Included by ctest in tests/core, tests/io and tests/fronts (wavecam_test_costs): the seconds the
# slowest tests take on 2 cores two at a time, so that `ctest -j` starts them first and the run
# does not end on one of them alone. ctest prefers its own record (Testing/Temporary/CTestCostData.txt)
# once it has one; a name not in the directory is ignored.
foreach(cost_and_test
    100 OneSourceModel.AllThreeMethodsConvergeToOneImage
    180 WideField.KernelRunsMatchThePointSumsWithTheSamePhases
    113 WideField.ConvolutionMethodMatchesTheRayleighSommerfeldIntegral
    50 WideField.ConvolutionInDirectionCosinesMatchesTheRayleighSommerfeldIntegral
    90 WideField.KernelSummationAndPointSumsAtTheWidestFieldsMatchTheRayleighSommerfeldIntegral
    30 GpuSums.KernelSummationRunsMatchTheCpu
    87 ApplyCommand.TheEnvironmentChangesNoImageAndNoWordMeansTwoThings
    72 PhaseCode.RunsFromThePsfKeepEveryChannelWithinTwoPercentWhereThePsfIsWide
    64 KernelSummation.IncoherentMatchesTheExactIncoherentSum
    61 ApplyHostile.EveryTerminatingSignalDuringTheWriteKeepsTheOldOutput
    55 RandomPhaseNoise.PerChannelVarianceIsTheWavelengthSumAndFallsAsOneOverK
    45 Shares.EverySplitOfEveryJobShapeMergesToTheSingleRun
    45 Plugin.OiiotoolMatchesWavecamApply
    35 Shares.MergeEqualsTheSingleMachineRun
    32 nufft.FresnelZones.OnAxisIrradianceFollowsTheZoneCount
    28 WideField.PointSumsAndKernelSummationMatchTheRayleighSommerfeldIntegral)
  string(REGEX MATCH "^[0-9]+" cost "${cost_and_test}")
  if(cost)
    set(test_cost ${cost})
  else()
    set_tests_properties(${cost_and_test} PROPERTIES COST ${test_cost})
  endif()
endforeach()
