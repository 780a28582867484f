// Fixture (not compiled): a call in another system's folder, and the registry's macro defined
// here should not count as a call.
#define PENUMBRA_STABILITY(a, b, c) record(a, b, c)

TEST(Beta, EmptyCloudIsBlack) {
  PENUMBRA_STABILITY("an empty cloud", "zero lighting", "-");
}
