#include "stream/fact_base.hpp"

#include <algorithm>

namespace cluttertamp::stream::detail {

FactBase::FactBase(const pddl::Domain& domain, const StreamFile& streams) : domain_(domain), streams_(streams) {}

ObjectId FactBase::add_object(ObjectRecord record) {
  const ObjectId id = static_cast<ObjectId>(objects_.size());
  by_name_.emplace(record.name, id);
  objects_.push_back(std::move(record));
  return id;
}

std::optional<ObjectId> FactBase::find(const std::string& name) const {
  const auto it = by_name_.find(name);
  if (it == by_name_.end()) return std::nullopt;
  return it->second;
}

std::vector<ObjectId> FactBase::objects_of(const std::vector<std::string>& types, bool with_optimistic) const {
  std::vector<ObjectId> out;
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    const ObjectRecord& o = objects_[i];
    if (o.optimistic && !with_optimistic) continue;
    const bool fits = std::any_of(types.begin(), types.end(), [&](const std::string& wanted) {
      return std::any_of(o.types.begin(), o.types.end(), [&](const std::string& t) { return domain_.is_subtype(t, wanted); });
    });
    if (fits) out.push_back(static_cast<ObjectId>(i));
  }
  return out;
}

int FactBase::predicate_id(const std::string& name) {
  const auto [it, added] = predicate_ids_.emplace(name, static_cast<int>(predicate_names_.size()));
  if (added) predicate_names_.push_back(name);
  return it->second;
}

std::optional<FactKey> FactBase::ground(const pddl::Atom& atom, const Env& env) {
  FactKey key{predicate_id(atom.predicate)};
  for (const pddl::Term& t : atom.args) {
    if (t.variable) {
      const auto it = env.find(t.name);
      if (it == env.end()) return std::nullopt;
      key.push_back(it->second);
    } else {
      const auto id = find(t.name);
      if (!id) return std::nullopt;
      key.push_back(*id);
    }
  }
  return key;
}

std::string FactBase::str(const FactKey& fact) const {
  std::string out = "(" + predicate_name(fact[0]);
  for (std::size_t i = 1; i < fact.size(); ++i) out += " " + object(fact[i]).name;
  return out + ")";
}

bool FactBase::add_fact(const FactKey& fact, const FactInfo& info) {
  const auto it = facts_.find(fact);
  if (it == facts_.end()) {
    by_predicate_[fact[0]].push_back(&*facts_.emplace(fact, info).first);
    return true;
  }
  if (it->second.optimistic && !info.optimistic) {
    it->second = info;
    return true;
  }
  return false;
}

const FactInfo* FactBase::fact(const FactKey& fact) const {
  const auto it = facts_.find(fact);
  return it == facts_.end() ? nullptr : &it->second;
}

std::size_t FactBase::fact_count(const std::string& predicate) {
  const auto it = by_predicate_.find(predicate_id(predicate));
  return it == by_predicate_.end() ? 0 : it->second.size();
}

void FactBase::add_state_fact(const FactKey& fact, const FactInfo& info) { state_facts_[fact].push_back(info); }

const FactInfo* FactBase::real_fact(const FactKey& fact) const {
  if (const FactInfo* info = this->fact(fact); info && !info->optimistic) return info;
  const auto it = state_facts_.find(fact);
  return it == state_facts_.end() ? nullptr : &it->second.front();
}

bool FactBase::holds_in_state(const FactKey& fact, const State& state) {
  const auto it = state_facts_.find(fact);
  if (it == state_facts_.end()) return false;
  return std::any_of(it->second.begin(), it->second.end(), [&](const FactInfo& info) {
    const Instance& certifier = *instances_[static_cast<std::size_t>(info.certifier)];
    return fluent_state(state, certifier.stream) == certifier.fluent_state;
  });
}

std::vector<FactKey> FactBase::fluent_state(const State& state, int stream) {
  std::vector<FactKey> out;
  for (const std::string& name : decl(stream).fluents) {
    const int predicate = predicate_id(name);
    for (auto it = state.lower_bound(FactKey{predicate}); it != state.end() && (*it)[0] == predicate; ++it) out.push_back(*it);
  }
  std::sort(out.begin(), out.end());
  return out;
}

void FactBase::clear_optimistic() {
  for (auto& [predicate, list] : by_predicate_) {
    list.erase(std::remove_if(list.begin(), list.end(), [](const FactEntry* e) { return e->second.optimistic; }), list.end());
  }
  for (auto it = facts_.begin(); it != facts_.end();) {
    it = it->second.optimistic ? facts_.erase(it) : std::next(it);
  }
}

void FactBase::bindings(const std::vector<pddl::Term>& inputs, const std::vector<pddl::Atom>& domain,
                        bool with_optimistic, const std::function<void(const std::vector<ObjectId>&, int)>& visit) {
  // Variables become slots, so that matching compares integers instead of names.
  std::map<std::string, int> slot_of;
  auto slot = [&](const std::string& name) { return slot_of.emplace(name, static_cast<int>(slot_of.size())).first->second; };
  std::vector<Pattern> patterns;
  for (const pddl::Atom& a : domain) {
    Pattern p{predicate_id(a.predicate), {}};
    for (const pddl::Term& t : a.args) {
      const auto id = t.variable ? std::nullopt : find(t.name);
      p.args.push_back(t.variable ? slot(t.name) : id ? -1 - *id : kNoObject);
    }
    patterns.push_back(std::move(p));
  }
  // Inputs that no domain atom binds range over every real object.
  std::vector<int> free, input_slots;
  for (const pddl::Term& in : inputs) {
    if (!slot_of.count(in.name)) free.push_back(slot(in.name));
    input_slots.push_back(slot_of.at(in.name));
  }
  const std::vector<ObjectId> everything = free.empty() ? std::vector<ObjectId>{} : objects_of({"object"}, false);
  std::vector<ObjectId> slots(slot_of.size(), -1);
  std::vector<ObjectId> values(inputs.size());
  match(patterns, 0, slots, 0, with_optimistic, [&](int complexity) {
    std::function<void(std::size_t)> each = [&](std::size_t k) {
      if (k == free.size()) {
        for (std::size_t i = 0; i < input_slots.size(); ++i) values[i] = slots[static_cast<std::size_t>(input_slots[i])];
        visit(values, complexity);
        return;
      }
      for (ObjectId o : everything) {
        slots[static_cast<std::size_t>(free[k])] = o;
        each(k + 1);
      }
    };
    each(0);
  });
}

void FactBase::match(const std::vector<Pattern>& patterns, std::size_t i, std::vector<ObjectId>& slots, int complexity,
                     bool with_optimistic, const std::function<void(int)>& visit) const {
  if (i == patterns.size()) return visit(complexity);
  const Pattern& pattern = patterns[i];
  const auto list_it = by_predicate_.find(pattern.predicate);
  if (list_it == by_predicate_.end()) return;
  std::vector<std::size_t> bound_here;
  // By index: `visit` may add facts to this very list (the entries themselves stay put).
  for (std::size_t k = 0, n = list_it->second.size(); k < n; ++k) {
    const FactEntry& entry = *list_it->second[k];
    const FactKey& fact = entry.first;
    if (fact.size() != pattern.args.size() + 1 || (entry.second.optimistic && !with_optimistic)) continue;
    bound_here.clear();
    bool fits = true;
    for (std::size_t a = 0; a < pattern.args.size() && fits; ++a) {
      const int arg = pattern.args[a];
      const ObjectId value = fact[a + 1];
      if (arg < 0) {
        fits = arg != kNoObject && -1 - arg == value;
      } else if (ObjectId& bound = slots[static_cast<std::size_t>(arg)]; bound >= 0) {
        fits = bound == value;
      } else {
        bound = value;
        bound_here.push_back(static_cast<std::size_t>(arg));
      }
    }
    if (fits) match(patterns, i + 1, slots, std::max(complexity, entry.second.complexity), with_optimistic, visit);
    for (std::size_t s : bound_here) slots[s] = -1;
  }
}

int FactBase::instance(int stream, const std::vector<ObjectId>& inputs,
                       const std::optional<std::vector<FactKey>>& fluent_state) {
  const auto key = std::make_tuple(stream, inputs, fluent_state);
  if (const auto it = instance_ids_.find(key); it != instance_ids_.end()) return it->second;
  auto made = std::make_unique<Instance>();
  made->stream = stream;
  made->inputs = inputs;
  made->fluent_state = fluent_state;
  made->real = std::none_of(inputs.begin(), inputs.end(), [&](ObjectId o) { return object(o).optimistic; });
  const int id = static_cast<int>(instances_.size());
  instances_.push_back(std::move(made));
  instance_ids_.emplace(key, id);
  return id;
}

Env FactBase::env_of(const Instance& instance, const std::vector<ObjectId>* outputs) const {
  const StreamDecl& d = decl(instance.stream);
  Env env;
  for (std::size_t i = 0; i < d.inputs.size(); ++i) env[d.inputs[i].name] = instance.inputs[i];
  if (outputs) {
    for (std::size_t i = 0; i < d.outputs.size() && i < outputs->size(); ++i) env[d.outputs[i].name] = (*outputs)[i];
  }
  return env;
}

}  // namespace cluttertamp::stream::detail
