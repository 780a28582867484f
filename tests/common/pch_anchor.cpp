// The translation unit that builds the test executables' shared precompiled header
// (tests/CMakeLists.txt, penumbra_test_pch); it has no tests of its own.
int main() {
  return 0;
}
