// The unit that carries the test units' shared precompiled header (tests/CMakeLists.txt,
// sglab_test_pch); it defines nothing.
