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
    facts_.emplace(fact, info);
    by_predicate_[fact[0]].push_back(fact);
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
  for (auto it = facts_.begin(); it != facts_.end();) {
    it = it->second.optimistic ? facts_.erase(it) : std::next(it);
  }
  for (auto& [predicate, list] : by_predicate_) {
    list.erase(std::remove_if(list.begin(), list.end(), [&](const FactKey& f) { return !facts_.count(f); }), list.end());
  }
}

void FactBase::bindings(const std::vector<pddl::Term>& inputs, const std::vector<pddl::Atom>& domain,
                        bool with_optimistic, const std::function<void(const std::vector<ObjectId>&, int)>& visit) {
  // Inputs that no domain atom binds range over every real object.
  std::vector<std::string> free;
  for (const pddl::Term& in : inputs) {
    const bool covered = std::any_of(domain.begin(), domain.end(), [&](const pddl::Atom& a) {
      return std::any_of(a.args.begin(), a.args.end(), [&](const pddl::Term& t) { return t.name == in.name; });
    });
    if (!covered) free.push_back(in.name);
  }
  const std::vector<ObjectId> everything = objects_of({"object"}, false);
  Env env;
  match(domain, 0, env, 0, with_optimistic, [&](const Env& bound, int complexity) {
    Env local = bound;
    std::function<void(std::size_t)> each = [&](std::size_t k) {
      if (k == free.size()) {
        std::vector<ObjectId> values;
        for (const pddl::Term& in : inputs) values.push_back(local.at(in.name));
        visit(values, complexity);
        return;
      }
      for (ObjectId o : everything) {
        local[free[k]] = o;
        each(k + 1);
      }
    };
    each(0);
  });
}

void FactBase::match(const std::vector<pddl::Atom>& domain, std::size_t i, Env& env, int complexity, bool with_optimistic,
                     const std::function<void(const Env&, int)>& visit) {
  if (i == domain.size()) return visit(env, complexity);
  const pddl::Atom& atom = domain[i];
  const auto list_it = by_predicate_.find(predicate_id(atom.predicate));
  if (list_it == by_predicate_.end()) return;
  // By index and by copy: `visit` may add facts to this very list.
  for (std::size_t k = 0, n = list_it->second.size(); k < n; ++k) {
    const FactKey fact = list_it->second[k];
    if (fact.size() != atom.args.size() + 1) continue;
    const FactInfo& info = facts_.at(fact);
    if (info.optimistic && !with_optimistic) continue;
    std::vector<std::string> bound_here;
    bool fits = true;
    for (std::size_t a = 0; a < atom.args.size() && fits; ++a) {
      const pddl::Term& t = atom.args[a];
      if (!t.variable) {
        const auto id = find(t.name);
        fits = id && *id == fact[a + 1];
      } else if (const auto it = env.find(t.name); it != env.end()) {
        fits = it->second == fact[a + 1];
      } else {
        env[t.name] = fact[a + 1];
        bound_here.push_back(t.name);
      }
    }
    if (fits) match(domain, i + 1, env, std::max(complexity, info.complexity), with_optimistic, visit);
    for (const std::string& v : bound_here) env.erase(v);
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
