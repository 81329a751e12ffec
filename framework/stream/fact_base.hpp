#pragma once
// Internal: the objects, facts and stream instances a stream search works on.

#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "cluttertamp/pddl/ast.hpp"
#include "cluttertamp/plugin/stream_sampler.hpp"
#include "cluttertamp/stream/stream_file.hpp"

namespace cluttertamp::stream::detail {

using ObjectId = int;
/// A ground fact: its predicate's id, then its arguments' object ids.
using FactKey = std::vector<int>;
using Env = std::map<std::string, ObjectId>;  ///< ?variable -> object
/// The fluent facts that hold in a state; static facts live in the FactBase.
using State = std::set<FactKey>;

struct ObjectRecord {
  std::string name;
  std::vector<std::string> types{"object"};
  std::optional<plugin::StreamValue> value;  ///< absent: the object is its name
  bool optimistic = false;                   ///< stands for a stream output not yet made
  int maker = -1;                            ///< optimistic: the instance it is an output of
};

/// One stream (or rule, predicate, function) applied to fixed inputs. Real when every
/// input is a real object; then it may own a generator. A stream with :fluents has one
/// instance per inputs without a state, which only stands for optimistic outputs, and
/// one per state it is evaluated in, whose certified facts hold in that state only.
struct Instance {
  int stream = 0;  ///< index into StreamFile::streams
  std::vector<ObjectId> inputs;
  /// :fluents: the facts of its fluent predicates in the state it is evaluated in.
  std::optional<std::vector<FactKey>> fluent_state;
  bool real = true;
  std::unique_ptr<plugin::StreamGenerator> generator;
  int calls = 0;
  bool exhausted = false;
  bool disabled = false;  ///< adaptive: evaluated at this level; no optimistic outputs
  std::vector<std::vector<ObjectId>> results;  ///< outputs of each value made
  std::optional<double> value;                 ///< function: its value once evaluated
  std::vector<ObjectId> optimistic_outputs;    ///< one optimistic object per output
};

struct FactInfo {
  bool optimistic = false;
  int complexity = 0;   ///< 0 for initial facts; grows with the streams behind a fact
  int certifier = -1;   ///< the instance that certified it; -1 for initial facts
};

/// Objects, predicates, facts (real ones and, for the adaptive search, optimistic ones)
/// and the stream instances made so far.
class FactBase {
 public:
  FactBase(const pddl::Domain& domain, const StreamFile& streams);
  FactBase(const FactBase&) = delete;  // by_predicate_ points into facts_
  FactBase& operator=(const FactBase&) = delete;

  // Objects.
  ObjectId add_object(ObjectRecord record);
  std::optional<ObjectId> find(const std::string& name) const;
  const ObjectRecord& object(ObjectId id) const { return objects_[static_cast<std::size_t>(id)]; }
  std::size_t object_count() const { return objects_.size(); }
  /// Objects whose type is `type` or descends from it (optimistic ones only if asked).
  std::vector<ObjectId> objects_of(const std::vector<std::string>& types, bool with_optimistic) const;

  // Facts.
  int predicate_id(const std::string& name);
  const std::string& predicate_name(int id) const { return predicate_names_[static_cast<std::size_t>(id)]; }
  /// The fact of `atom` under `env`; nothing when a constant is unknown or a variable unbound.
  std::optional<FactKey> ground(const pddl::Atom& atom, const Env& env);
  std::string str(const FactKey& fact) const;
  /// Adds a fact unless it is already real; a real fact replaces an optimistic one.
  /// Returns true when the fact is new or became real.
  bool add_fact(const FactKey& fact, const FactInfo& info);
  const FactInfo* fact(const FactKey& fact) const;
  void clear_optimistic();
  const std::map<FactKey, FactInfo>& facts() const { return facts_; }
  /// Facts of `predicate`, optimistic ones included.
  std::size_t fact_count(const std::string& predicate);

  /// A fact an instance with a fluent state certified: it holds in that state only, so
  /// it is kept apart from the facts above (which the symbolic search sees).
  void add_state_fact(const FactKey& fact, const FactInfo& info);
  /// The fact as a real one: a state-free fact, or else one certified in some state.
  const FactInfo* real_fact(const FactKey& fact) const;
  /// Whether an instance certified `fact` in a state agreeing with `state` on its fluents.
  bool holds_in_state(const FactKey& fact, const State& state);
  const std::map<FactKey, std::vector<FactInfo>>& state_facts() const { return state_facts_; }
  /// `state` restricted to the :fluents predicates of `stream` (sorted).
  std::vector<FactKey> fluent_state(const State& state, int stream);

  /// Calls `visit` for every binding of `inputs` under which each atom of `domain` is a
  /// fact (optimistic ones only if allowed); inputs no atom mentions range over the
  /// real objects. `visit` receives the inputs' objects and the highest complexity of
  /// the matched facts.
  void bindings(const std::vector<pddl::Term>& inputs, const std::vector<pddl::Atom>& domain, bool with_optimistic,
                const std::function<void(const std::vector<ObjectId>&, int)>& visit);

  // Instances.
  /// The instance of `stream` on `inputs` (in `fluent_state`, for :fluents), made on first use.
  int instance(int stream, const std::vector<ObjectId>& inputs,
               const std::optional<std::vector<FactKey>>& fluent_state = std::nullopt);
  Instance& instance_at(int id) { return *instances_[static_cast<std::size_t>(id)]; }
  std::size_t instance_count() const { return instances_.size(); }
  /// The environment of an instance's declaration for its inputs and, when given, outputs.
  Env env_of(const Instance& instance, const std::vector<ObjectId>* outputs = nullptr) const;

  const StreamFile& streams() const { return streams_; }
  const StreamDecl& decl(int stream) const { return streams_.streams[static_cast<std::size_t>(stream)]; }

 private:
  /// A domain atom with its variables as slots of a binding.
  struct Pattern {
    int predicate = 0;
    std::vector<int> args;  ///< >= 0: a slot; < 0: the object -1 - arg (kNoObject: an unknown constant)
  };
  static constexpr int kNoObject = std::numeric_limits<int>::min();
  void match(const std::vector<Pattern>& patterns, std::size_t i, std::vector<ObjectId>& slots, int complexity,
             bool with_optimistic, const std::function<void(int)>& visit) const;

  const pddl::Domain& domain_;
  const StreamFile& streams_;
  std::vector<ObjectRecord> objects_;
  std::map<std::string, ObjectId> by_name_;
  std::vector<std::string> predicate_names_;
  std::map<std::string, int> predicate_ids_;
  std::map<FactKey, FactInfo> facts_;
  using FactEntry = std::pair<const FactKey, FactInfo>;
  std::map<int, std::vector<const FactEntry*>> by_predicate_;  // every fact in facts_, optimistic ones too
  std::vector<std::unique_ptr<Instance>> instances_;
  std::map<FactKey, std::vector<FactInfo>> state_facts_;
  std::map<std::tuple<int, std::vector<ObjectId>, std::optional<std::vector<FactKey>>>, int> instance_ids_;
};

}  // namespace cluttertamp::stream::detail
