#include "rigel/io/bvh.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "rigel/math/rotation.h"

namespace rigel::io {
namespace {

constexpr std::size_t kMaxJoints = 100000;
constexpr std::size_t kMaxDepth = 1000;

// 0.0001, 1000: seconds as people write them.
std::string format_seconds(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

struct Token {
  std::string_view text;
  std::uint32_t line;
};

std::vector<Token> tokenize(std::string_view text) {
  std::vector<Token> tokens;
  std::uint32_t line = 1;
  std::size_t i = 0;
  while (i < text.size()) {
    char c = text[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
    } else if (c == '{' || c == '}') {
      tokens.push_back({text.substr(i, 1), line});
      ++i;
    } else {
      std::size_t start = i;
      while (i < text.size() && !std::isspace(static_cast<unsigned char>(text[i])) && text[i] != '{' && text[i] != '}') ++i;
      tokens.push_back({text.substr(start, i - start), line});
    }
  }
  return tokens;
}

class Parser {
 public:
  Parser(std::string_view text, const std::string& source) : tokens_(tokenize(text)), source_(source) {}

  Result<BvhFile> parse() {
    if (Status s = expect("HIERARCHY"); !s) return s;
    if (at_end() || peek().text != "ROOT") return fail("expected ROOT after HIERARCHY");
    // Joints: an explicit stack, so deep files cannot overflow ours.
    std::vector<std::int32_t> stack;
    while (!at_end() && peek().text != "MOTION") {
      const Token& t = next();
      if (t.text == "ROOT" || t.text == "JOINT" || t.text == "End") {
        if (t.text == "ROOT" && !stack.empty()) return fail_at(t, "ROOT inside another joint");
        if (t.text != "ROOT" && stack.empty()) return fail_at(t, std::string(t.text) + " outside any joint");
        if (stack.size() >= kMaxDepth) return fail_at(t, "joints nested deeper than " + std::to_string(kMaxDepth));
        if (file_.joints.size() >= kMaxJoints) return fail_at(t, "more than " + std::to_string(kMaxJoints) + " joints");
        BvhJoint joint;
        joint.line = t.line;
        joint.parent = stack.empty() ? -1 : stack.back();
        if (joint.parent >= 0 && file_.joints[static_cast<std::size_t>(joint.parent)].end_site)
          return fail_at(t, "an End Site cannot have children");
        if (t.text == "End") {
          if (at_end() || peek().text != "Site") return fail_at(t, "expected 'Site' after 'End'");
          next();
          joint.end_site = true;
          joint.name = file_.joints[static_cast<std::size_t>(joint.parent)].name + "_end";
        } else {
          if (at_end() || peek().text == "{") return fail_at(t, "expected a name after " + std::string(t.text));
          joint.name = std::string(next().text);
        }
        if (Status s = expect("{", "after " + std::string(t.text) + " " + joint.name); !s) return s;
        if (Status s = expect("OFFSET", "in " + joint.name); !s) return s;
        for (int k = 0; k < 3; ++k) {
          Result<double> v = number("OFFSET of " + joint.name);
          if (!v) return v.status();
          joint.offset[k] = *v;
        }
        if (!joint.end_site && !at_end() && peek().text == "CHANNELS") {
          next();
          Result<double> n = number("CHANNELS count of " + joint.name);
          if (!n) return n.status();
          if (*n < 0 || *n > 6 || *n != std::floor(*n)) return fail_line(read_line_, "CHANNELS of " + joint.name + ": count must be 0 to 6");
          joint.first_channel = file_.channel_count;
          unsigned seen = 0;
          for (int k = 0; k < static_cast<int>(*n); ++k) {
            if (at_end()) return fail("CHANNELS of " + joint.name + ": file ends early");
            const Token& c = next();
            static constexpr std::pair<std::string_view, BvhChannel> kNames[] = {
                {"Xposition", BvhChannel::kXposition}, {"Yposition", BvhChannel::kYposition},
                {"Zposition", BvhChannel::kZposition}, {"Xrotation", BvhChannel::kXrotation},
                {"Yrotation", BvhChannel::kYrotation}, {"Zrotation", BvhChannel::kZrotation}};
            bool known = false;
            for (const auto& [name, channel] : kNames) {
              if (c.text != name) continue;
              known = true;
              unsigned bit = 1u << static_cast<unsigned>(channel);
              if (seen & bit) return fail_at(c, "channel " + std::string(name) + " repeated in " + joint.name);
              seen |= bit;
              joint.channels.push_back(channel);
            }
            if (!known) return fail_at(c, "unknown channel '" + std::string(c.text) + "' in " + joint.name);
          }
          file_.channel_count += static_cast<std::uint32_t>(joint.channels.size());
        }
        stack.push_back(static_cast<std::int32_t>(file_.joints.size()));
        file_.joints.push_back(std::move(joint));
      } else if (t.text == "}") {
        if (stack.empty()) return fail_at(t, "unbalanced '}'");
        stack.pop_back();
      } else {
        return fail_at(t, "unexpected '" + std::string(t.text) + "' in HIERARCHY");
      }
    }
    if (!stack.empty()) {
      return fail("joint " + file_.joints[static_cast<std::size_t>(stack.back())].name + " (line " +
                  std::to_string(file_.joints[static_cast<std::size_t>(stack.back())].line) + ") is not closed with '}'");
    }
    if (file_.joints.empty()) return fail("no joints in HIERARCHY");
    if (Status s = expect("MOTION"); !s) return s;
    if (Status s = expect("Frames:"); !s) return s;
    Result<double> frames = number("Frames");
    if (!frames) return frames.status();
    if (*frames < 0 || *frames != std::floor(*frames) || *frames > kBvhMaxFrames)
      return fail_line(read_line_, "Frames must be a whole number from 0 to " + std::to_string(static_cast<std::uint64_t>(kBvhMaxFrames)) +
                                       ", not " + std::string(tokens_[pos_ - 1].text));
    file_.frame_count = static_cast<std::uint32_t>(*frames);
    if (Status s = expect("Frame"); !s) return s;
    if (Status s = expect("Time:"); !s) return s;
    Result<double> frame_time = number("Frame Time");
    if (!frame_time) return frame_time.status();
    if (!(*frame_time >= kBvhMinFrameTime && *frame_time <= kBvhMaxFrameTime))
      return fail_line(read_line_, "Frame Time must be from " + format_seconds(kBvhMinFrameTime) + " to " + format_seconds(kBvhMaxFrameTime) +
                                       " seconds (" + format_seconds(1.0 / kBvhMaxFrameTime) + " to " + format_seconds(1.0 / kBvhMinFrameTime) +
                                       " frames per second), not " + std::string(tokens_[pos_ - 1].text));
    file_.frame_time = *frame_time;
    const std::size_t expected = std::size_t{file_.frame_count} * file_.channel_count;
    const std::size_t available = tokens_.size() - pos_;
    if (available != expected) {
      std::size_t row = file_.channel_count == 0 ? 0 : std::min(available, expected) / file_.channel_count;
      return fail_line(available < expected ? last_line() : tokens_[pos_ + expected].line,
                       "motion has " + std::to_string(available) + " values, expected " + std::to_string(file_.frame_count) +
                           " frames x " + std::to_string(file_.channel_count) + " channels = " + std::to_string(expected) +
                           " (complete rows: " + std::to_string(row) + ")");
    }
    file_.motion.reserve(expected);
    for (std::size_t i = 0; i < expected; ++i) {
      Result<double> v = number("motion value");
      if (!v) return v.status();
      file_.motion.push_back(*v);
    }
    return std::move(file_);
  }

 private:
  bool at_end() const { return pos_ >= tokens_.size(); }
  const Token& peek() const { return tokens_[pos_]; }
  const Token& next() {
    read_line_ = tokens_[pos_].line;
    return tokens_[pos_++];
  }
  std::uint32_t last_line() const { return tokens_.empty() ? 1 : tokens_.back().line; }

  Status fail_line(std::uint32_t line, const std::string& message) const {
    return error(ErrorCode::kParseError, source_ + ":" + std::to_string(line) + ": " + message);
  }
  Status fail_at(const Token& t, const std::string& message) const { return fail_line(t.line, message); }
  Status fail(const std::string& message) const {
    return fail_line(at_end() ? last_line() : peek().line, message);
  }
  Status expect(std::string_view word, const std::string& context = "") {
    if (at_end()) return fail("expected '" + std::string(word) + "'" + (context.empty() ? "" : " " + context) + ", found the end of the file");
    if (peek().text != word)
      return fail("expected '" + std::string(word) + "'" + (context.empty() ? "" : " " + context) + ", found '" + std::string(peek().text) + "'");
    next();
    return Status::ok();
  }
  Result<double> number(const std::string& what) {
    if (at_end()) return fail("expected a number for " + what + ", found the end of the file");
    const Token& t = next();
    double v = 0.0;
    const char* begin = t.text.data();
    const char* end = begin + t.text.size();
    if (begin != end && *begin == '+') ++begin;
    auto [ptr, ec] = std::from_chars(begin, end, v);
    if (ec != std::errc() || ptr != end || !std::isfinite(v))
      return fail_at(t, "expected a finite number for " + what + ", found '" + std::string(t.text) + "'");
    return v;
  }

  std::vector<Token> tokens_;
  std::size_t pos_ = 0;
  std::uint32_t read_line_ = 1;  // line of the token read last
  std::string source_;
  BvhFile file_;
};

}  // namespace

Result<BvhFile> parse_bvh(std::string_view text, const std::string& source) { return Parser(text, source).parse(); }

Result<BvhFile> load_bvh(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return error(ErrorCode::kIoError, path + ": cannot open");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return parse_bvh(buffer.str(), path);
}

int bvh_rotate_order(const BvhJoint& joint) {
  std::string applied;  // first-applied axis first
  for (auto it = joint.channels.rbegin(); it != joint.channels.rend(); ++it) {
    switch (*it) {
      case BvhChannel::kXrotation: applied += 'x'; break;
      case BvhChannel::kYrotation: applied += 'y'; break;
      case BvhChannel::kZrotation: applied += 'z'; break;
      default: break;
    }
  }
  for (char axis : {'x', 'y', 'z'}) {
    if (applied.find(axis) == std::string::npos) applied += axis;
  }
  return static_cast<int>(*math::rotate_order_from_name(applied));
}

}  // namespace rigel::io
