#pragma once

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/export.hpp"
#include "cluttertamp/pddl/ast.hpp"

namespace cluttertamp::stream {

/// One declaration of a PDDLStream stream file.
///  - stream:    (:stream NAME :inputs (?x...) :domain CONJ :outputs (?y...) :certified CONJ
///               [:fluents (PREDICATE...)]); without outputs it is a test.
///  - predicate: (:predicate (P ?x...) CONJ): a boolean test certifying (P ?x...).
///  - function:  (:function (F ?x...) CONJ): the value of a cost term (F ?x...).
///  - rule:      (:rule :inputs (?x...) :domain CONJ :certified CONJ): facts that follow
///               from others, with no code behind them.
/// Every symbol is lower-cased, as in PDDL.
struct StreamDecl {
  enum class Kind { stream, predicate, function, rule };
  Kind kind = Kind::stream;
  /// stream: its name; predicate and function: the head's name; rule: "rule@LINE".
  std::string name;
  std::vector<pddl::Term> inputs;      ///< variables; predicate/function: the head's
  std::vector<pddl::Atom> domain;      ///< the facts the inputs must satisfy
  std::vector<pddl::Term> outputs;     ///< variables, new values the stream makes
  std::vector<pddl::Atom> certified;   ///< predicate: the head; function: empty
  std::vector<std::string> fluents;    ///< predicates of the state the stream reads
  pddl::Atom head;                     ///< predicate and function: (name ?x...)
  SourceLocation where;

  bool is_test() const { return kind == Kind::predicate || (kind == Kind::stream && outputs.empty()); }
};

struct StreamFile {
  std::string name;
  std::string file;
  std::vector<StreamDecl> streams;
  SourceLocation where;
  /// What was suspect but accepted (a :function the domain does not declare), located.
  std::vector<Diagnostic> warnings;

  /// The declaration named `name`, or null.
  const StreamDecl* find(const std::string& name) const;
};

/// Parses a stream file and validates it as PDDLStream does: inputs and outputs are
/// distinct ?variables, no variable is both an input and an output, every variable of
/// :domain is an input, every variable of :certified an input or an output. Given a
/// domain, also: a predicate the domain declares has that many arguments and, in
/// :domain and :certified, is static (no action changes it, it is not derived);
/// predicates the domain does not declare are the streams' own (as in PDDLStream);
/// :fluents names predicates that actions change; a :function's head is declared in
/// (:functions ...) or else is accepted with a warning. Throws InputError listing every problem (file:line:column, what
/// is wrong, an excerpt with a caret). `:optimizer` and other PDDLStream extensions
/// are refused by name.
CLUTTERTAMP_API StreamFile parse_stream_file(const std::string& text, const std::string& file,
                                             const pddl::Domain* domain = nullptr);
CLUTTERTAMP_API StreamFile load_stream_file(const std::filesystem::path& file, const pddl::Domain* domain = nullptr);

/// Predicates that some action adds or deletes (fluents), derived ones excluded.
CLUTTERTAMP_API std::set<std::string> changed_predicates(const pddl::Domain& domain);

}  // namespace cluttertamp::stream
