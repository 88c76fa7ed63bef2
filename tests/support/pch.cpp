// The translation unit that builds the test suite's precompiled headers (tests/CMakeLists.txt):
// its header list is the one the test executables reuse; it has no code of its own.
