# tests/ctest_costs.cmake: read by ctest after the discovered gtest entries (TEST_INCLUDE_FILES,
# tests/CMakeLists.txt), in both builds. ctest -j starts entries in descending COST; once a build
# directory has Testing/Temporary/CTestCostData.txt (after its first run) the measured times replace
# these. CI runs on a clean clone, where without them ctest starts entries in the order they were
# added, and a long entry added late (a fit in test_fit.cpp, near the end of the alphabet) starts
# last and ends the run alone while the other core idles. The longest entries are listed here with
# their CPU seconds under ASan + UBSan (2026-12-06, ANISO_TEST_SCALE 0.25; the release build takes
# the same order, behind its package tests, tests/package/CMakeLists.txt), and labelled "slow"
# (`ctest -LE slow` leaves them out of a quick local run). An entry of more than about 20 s under
# the sanitizers belongs here; ctest_every_entry_has_a_timeout fails when a name here is no entry.
# With one entry per test suite (the sanitizer build, tests/gtest_suites.cmake), a gtest name's
# seconds are added to its suite's entry, whose COST starts at its number of tests.
macro(aniso_cost name seconds)
  if(ANISO_GTEST_GROUPED AND "${name}" MATCHES "^([^.]+)\\.")
    set(aniso_cost_suite "${CMAKE_MATCH_1}")
    if(NOT DEFINED "aniso_suite_cost_${aniso_cost_suite}")
      set("aniso_suite_cost_${aniso_cost_suite}" 0) # no such suite: ctest_every_entry_has_a_timeout says so
    endif()
    math(EXPR "aniso_suite_cost_${aniso_cost_suite}" "${aniso_suite_cost_${aniso_cost_suite}} + ${seconds}")
    set_tests_properties(${aniso_cost_suite} PROPERTIES COST ${aniso_suite_cost_${aniso_cost_suite}} LABELS slow)
  else()
    set_tests_properties(${name} PROPERTIES COST ${seconds} LABELS slow)
  endif()
endmacro()

# CPU seconds under ASan + UBSan, measured alone (docs/testing.md, "CI time").
aniso_cost(FitIdentifiability.CornellPaintsTieWhatTheDataCannotSeeAndKeepAlbedoBelowOne 130)
aniso_cost(ExportFit.StandardMaterialsPerTarget 95)
aniso_cost(CliHabits.FitIsBitIdenticalWhateverTheThreadCount 55)
aniso_cost(python_test_fit_db 50)
