// The target that builds the test executables' precompiled GoogleTest header
// (tests/CMakeLists.txt, penumbra_test_pch); other test targets reuse it.
int main() {
  return 0;
}
