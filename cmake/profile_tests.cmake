# vknerf_add_profile_tests(TARGET PROFILE...): the stage tests (tests/unit/) once more under each
# device profile (src/gpu/device/device_profile.h), as ctest entries PROFILE.Suite.Test: lavapipe with
# that class of device's missing features, limits, memory model and NaN-filled buffers, under the
# validation layer's synchronization validation as every other entry.
#
# Left out: the suites that drive the command line (their stages are in the rest) and two MLP
# comparisons that repeat, at the cost of a minute under a profile, the paths DwPaths/* cover.
set(VKNERF_PROFILE_SKIPPED_TESTS
    CameraPathTest.* NgpCameraPathTest.* PointExportCli.* MeshExportCli.*
    MlpNerf.FusedForwardMatchesTheLayeredOne MlpNerf.ColourBiasIsTheVectorAsInputColumns)

function(vknerf_add_profile_tests target)
  set(suites "")
  file(GLOB_RECURSE sources CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/tests/unit/*.cpp)
  foreach(src ${sources})
    file(STRINGS ${src} lines REGEX "^TEST(_F|_P)?\\(")
    foreach(line ${lines})
      string(REGEX REPLACE "^TEST(_F|_P)?\\(([A-Za-z0-9_]+),.*" "\\2" suite "${line}")
      list(APPEND suites ${suite})
    endforeach()
  endforeach()
  list(REMOVE_DUPLICATES suites)
  set(positive "")
  foreach(suite ${suites})
    # A parameterized suite's cases are named Instantiation/Suite.Case/Parameter.
    list(APPEND positive "${suite}.*" "*/${suite}.*")
  endforeach()
  list(JOIN positive ":" positive)
  list(JOIN VKNERF_PROFILE_SKIPPED_TESTS ":" negative)
  foreach(profile ${ARGN})
    gtest_discover_tests(${target} DISCOVERY_MODE PRE_TEST DISCOVERY_TIMEOUT 60
      TEST_PREFIX "${profile}." TEST_FILTER "${positive}-${negative}" TEST_LIST vknerf_${profile}_tests)
    # gtest_discover_tests flattens a list-valued property, so the environment is set by a script
    # ctest runs after the discovery, over the names it found.
    set(script ${CMAKE_CURRENT_BINARY_DIR}/profile_${profile}_environment.cmake)
    file(WRITE ${script}
         "foreach(t IN LISTS vknerf_${profile}_tests)\n"
         "  set_tests_properties(\"\${t}\" PROPERTIES ENVIRONMENT \"${VKNERF_TEST_VALIDATION};VKNERF_DEVICE_PROFILE=${profile}\" LABELS profile)\n"
         "endforeach()\n")
    set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${script})
  endforeach()
endfunction()
