// The source of carve_test_pch, which exists only to build the test programs' shared precompiled
// header (tests/CMakeLists.txt); it defines nothing.
