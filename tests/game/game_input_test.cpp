// The valley game's per-step input and its recording file (game_input.h).
#include "penumbra/game/game_input.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "penumbra/assets/checksum.h"
#include "penumbra/assets/load_error.h"

namespace penumbra::game {
namespace {

InputRecording sample() {
  InputRecording r;
  r.steps.assign(20, GameInput{});
  r.steps.push_back({0, 0, 0, kButtonStart});
  for (int i = 0; i < 50; ++i)
    r.steps.push_back({static_cast<std::int8_t>(i - 25), 127, -127,
                       static_cast<std::uint8_t>(i % 3 == 0 ? kButtonDig : 0)});
  r.steps.insert(r.steps.end(), 30, GameInput{0, 127, 0, 0});
  return r;
}

std::string reason_of(const std::string& bytes) {
  try {
    parse_input_recording(bytes, "rec.pinput");
  } catch (const assets::LoadError& e) {
    EXPECT_EQ(e.file(), "rec.pinput");
    return e.reason();
  }
  ADD_FAILURE() << "accepted: " << bytes.substr(0, 60);
  return {};
}

TEST(GameInput, AxesAreQuantisedAndClamped) {
  EXPECT_EQ(quantize_axis(1.0f), 127);
  EXPECT_EQ(quantize_axis(-3.0f), -127);
  EXPECT_EQ(quantize_axis(0.5f), 64);
  EXPECT_EQ(quantize_axis(NAN), 0);
  const GameInput in{127, -127, 64, kButtonDig | kButtonPause};
  EXPECT_FLOAT_EQ(in.move().x, 1.0f);
  EXPECT_FLOAT_EQ(in.move().y, -1.0f);
  EXPECT_TRUE(in.held(kButtonDig));
  EXPECT_TRUE(in.held(kButtonPause));
  EXPECT_FALSE(in.held(kButtonStart));
}

TEST(GameInput, RecordingsRoundTripWithRunsOfEqualSteps) {
  const InputRecording r = sample();
  const std::string bytes = encode_input_recording(r);
  EXPECT_EQ(parse_input_recording(bytes, "x"), r);
  // The 20 idle steps and the 30 forward ones are one line each.
  EXPECT_NE(bytes.find("\n20 0 0 0 0\n"), std::string::npos);
  EXPECT_NE(bytes.find("\n30 0 127 0 0\n"), std::string::npos);
  EXPECT_EQ(parse_input_recording(encode_input_recording({}), "x").steps.size(), 0u);
}

TEST(GameInput, SavingIsAtomicAndLoadsBack) {
  const auto dir = std::filesystem::temp_directory_path() / "penumbra_game_input_test";
  std::filesystem::create_directories(dir);
  const auto file = dir / "a.pinput";
  save_input_recording(sample(), file);
  save_input_recording(sample(), file);  // over an existing file
  EXPECT_EQ(load_input_recording(file), sample());
  for (const auto& e : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(e.path().filename(), "a.pinput") << "left behind: " << e.path();
  EXPECT_THROW(load_input_recording(dir / "missing.pinput"), assets::LoadError);
  std::filesystem::remove_all(dir);
}

TEST(GameInput, BadRecordingsNameTheFileAndTheReason) {
  const std::string good = encode_input_recording(sample());
  const std::size_t eol = good.find('\n');
  const std::string payload = good.substr(eol + 1);
  EXPECT_EQ(reason_of(""), "empty file");
  EXPECT_NE(reason_of("hello\n").find("magic"), std::string::npos);
  EXPECT_NE(reason_of("penumbra-input 2 0 cbf29ce484222325\n").find("version 2"),
            std::string::npos);
  EXPECT_NE(reason_of(good.substr(0, good.size() - 5)).find("truncated"), std::string::npos);
  EXPECT_NE(reason_of(good + "1 0 0 0 0\n").find("after the payload"), std::string::npos);
  std::string flipped = good;
  flipped[eol + 3] = flipped[eol + 3] == '1' ? '2' : '1';
  EXPECT_NE(reason_of(flipped).find("checksum"), std::string::npos);
  // Well-formed files whose lines are not: re-encoded with a valid checksum.
  auto with_payload = [](const std::string& p) {
    char sum[17];
    std::snprintf(sum, sizeof sum, "%016llx",
                  static_cast<unsigned long long>(assets::fnv1a64(
                      {reinterpret_cast<const unsigned char*>(p.data()), p.size()})));
    return "penumbra-input 1 " + std::to_string(p.size()) + " " + sum + "\n" + p;
  };
  EXPECT_NE(reason_of(with_payload("1 0 0 0\n")).find("line 1"), std::string::npos);
  EXPECT_NE(reason_of(with_payload("1 0 0 0 0\n1 200 0 0 0\n")).find("line 2: value out of range"),
            std::string::npos);
  EXPECT_NE(reason_of(with_payload("0 0 0 0 0\n")).find("out of range"), std::string::npos);
  EXPECT_NE(reason_of(with_payload("1 0 0 0 32\n")).find("out of range"), std::string::npos);
  EXPECT_NE(reason_of(with_payload("16777216 0 0 0 0\n1 0 0 0 0\n")).find("more than"),
            std::string::npos);
}

}  // namespace
}  // namespace penumbra::game
