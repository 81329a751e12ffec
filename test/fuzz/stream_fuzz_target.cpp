// Fuzz target: a PDDLStream stream file, against the clutter domain. Read, or refused
// as bad input.
#include "cluttertamp/pddl/parser.hpp"
#include "cluttertamp/stream/stream_file.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fz = cluttertamp::fuzz;
  static const cluttertamp::pddl::Domain domain =
      cluttertamp::pddl::load_domain(std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "domains/pddl/clutter-streams/domain.pddl");
  const std::string text = fz::text(data, size);
  fz::refusing_bad_input([&] { cluttertamp::stream::parse_stream_file(text, "fuzz-stream.pddl", &domain); });
  fz::refusing_bad_input([&] { cluttertamp::stream::parse_stream_file(text, "fuzz-stream.pddl", nullptr); });
  return 0;
}
