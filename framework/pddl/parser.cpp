#include "cluttertamp/pddl/parser.hpp"

#include <algorithm>
#include <fstream>
#include <functional>
#include <sstream>
#include <string_view>
#include <unordered_map>
#include <unordered_set>

#include "cluttertamp/pddl/sexpr.hpp"
#include "cluttertamp/pddl/read_atom.hpp"

namespace cluttertamp::pddl {

namespace {

const std::set<std::string> kSupported = {
    ":strips",          ":typing",         ":negative-preconditions", ":disjunctive-preconditions",
    ":equality",        ":existential-preconditions", ":universal-preconditions", ":quantified-preconditions",
    ":conditional-effects", ":derived-predicates", ":action-costs", ":adl"};

// Requirements we know and refuse, with why.
const std::map<std::string, std::string> kRefused = {
    {":durative-actions", "temporal planning is not supported"},
    {":duration-inequalities", "temporal planning is not supported"},
    {":numeric-fluents", "numeric fluents beyond action costs are not supported"},
    {":fluents", "numeric fluents beyond action costs are not supported"},
    {":object-fluents", "object fluents are not supported"},
    {":timed-initial-literals", "timed initial literals are not supported"},
    {":preferences", "preferences are not supported"},
    {":constraints", "state-trajectory constraints are not supported"},
    {":continuous-effects", "continuous effects are not supported"},
};


// Shared machinery: error collection with excerpts, typed lists, formulas and effects.
class Reader {
 public:
  explicit Reader(SourceText source) : source_(std::move(source)) {}

  void error(const SourceLocation& where, const std::string& message) {
    diagnostics_.error(where, source_.with_excerpt(where, message));
  }
  void warning(const SourceLocation& where, const std::string& message) {
    diagnostics_.warning(where, source_.with_excerpt(where, message));
  }
  void finish() const { diagnostics_.throw_if_any(); }
  const SourceText& source() const { return source_; }

  // The single (define ...) of the file.
  const SExpr& define(const std::vector<SExpr>& top, const char* what) {
    if (top.empty()) source_.fail({source_.file, 1, 1}, std::string("empty file: expected (define (") + what + " ...) ...)");
    if (top.size() > 1) error(top[1].where, "text after the end of the (define ...)");
    if (!top[0].is_form("define") || top[0].items.size() < 2 || !top[0].items[1].is_form(what) ||
        top[0].items[1].items.size() != 2 || !top[0].items[1].items[1].is_atom()) {
      source_.fail(top[0].where, std::string("expected (define (") + what + " NAME) ...)");
    }
    return top[0];
  }

  // "a b - t c - (either t1 t2) d": names with their types ("object" when untyped).
  // `repeats_allowed`: a name may come twice. Only the placeholders of a predicate or
  // function declaration, where IPC domains write (in ?obj ?obj) and Fast Downward
  // accepts it, and :types, whose caller warns; anywhere else it is an error.
  std::vector<TypedName> typed_list(const std::vector<SExpr>& items, std::size_t first, bool variables,
                                    const std::string& what, bool repeats_allowed = false) {
    std::vector<TypedName> out;
    std::unordered_set<std::string_view> names;  // hashed: IPC problems list 100k objects and more
    std::size_t pending = 0;  // names waiting for a type
    for (std::size_t i = first; i < items.size(); ++i) {
      const SExpr& item = items[i];
      if (item.is("-")) {
        if (pending == 0) error(item.where, "'-' without names before it in " + what);
        if (i + 1 >= items.size()) {
          error(item.where, "'-' without a type after it in " + what);
          break;
        }
        const std::vector<std::string> types = type_spec(items[++i]);
        for (std::size_t k = out.size() - pending; k < out.size(); ++k) out[k].types = types;
        pending = 0;
        continue;
      }
      if (!item.is_atom()) {
        error(item.where, "expected a name in " + what);
        continue;
      }
      const bool is_variable = item.text[0] == '?';
      if (variables != is_variable || item.text.size() < (is_variable ? 2u : 1u) || item.text[0] == ':') {
        error(item.where, std::string("expected ") + (variables ? "a ?variable" : "a name") + " in " + what +
                              ", not '" + item.text + "'");
        continue;
      }
      if (!names.insert(item.text).second && !repeats_allowed) error(item.where, "'" + item.text + "' appears twice in " + what);
      out.push_back({item.text, {"object"}, item.where});
      ++pending;
    }
    return out;
  }

  static std::string join_types(const std::vector<std::string>& types) {
    if (types.size() == 1) return "'" + types[0] + "'";
    std::string out = "(either";
    for (const std::string& t : types) out += " " + t;
    return out + ")";
  }

  std::vector<std::string> type_spec(const SExpr& e) {
    if (e.is_atom()) return {e.text};
    if (e.is_form("either") && e.items.size() >= 2) {
      std::vector<std::string> types;
      for (std::size_t i = 1; i < e.items.size(); ++i) {
        if (e.items[i].is_atom()) types.push_back(e.items[i].text);
        else error(e.items[i].where, "expected a type name in (either ...)");
      }
      return types;
    }
    error(e.where, "expected a type name or (either TYPE...)");
    return {"object"};
  }

  std::optional<Atom> atom(const SExpr& e, const char* what) {
    NotAnAtom why{};
    SourceLocation where;
    auto a = read_atom(e, why, where);
    if (!a && why == NotAnAtom::head) error(where, std::string("expected ") + what + " (predicate arg...)");
    if (!a && why == NotAnAtom::argument) {
      error(where, "arguments must be names or ?variables; nested terms are not supported");
    }
    return a;
  }

  Formula formula(const SExpr& e) {
    Formula f;
    f.where = e.where;
    if (e.is_list && e.items.empty()) return f;  // () : true
    if (!e.is_list || !e.items[0].is_atom()) {
      error(e.where, "expected a condition: (and ...), (or ...), (not ...), (imply ...), (exists ...), (forall ...) or an atom");
      return f;
    }
    const std::string& head = e.items[0].text;
    auto children = [&](std::size_t from) {
      for (std::size_t i = from; i < e.items.size(); ++i) f.children.push_back(formula(e.items[i]));
    };
    if (head == "and" || head == "or") {
      f.kind = head == "and" ? Formula::Kind::conjunction : Formula::Kind::disjunction;
      children(1);
    } else if (head == "not") {
      f.kind = Formula::Kind::negation;
      if (e.items.size() != 2) error(e.where, "(not ...) takes one condition");
      else children(1);
    } else if (head == "imply") {
      f.kind = Formula::Kind::implication;
      if (e.items.size() != 3) error(e.where, "(imply IF THEN) takes two conditions");
      else children(1);
    } else if (head == "exists" || head == "forall") {
      f.kind = head == "exists" ? Formula::Kind::exists : Formula::Kind::forall;
      if (e.items.size() != 3 || !e.items[1].is_list) {
        error(e.where, "(" + head + " (?variable - type ...) CONDITION)");
        return f;
      }
      f.variables = typed_list(e.items[1].items, 0, true, "the variables of (" + head + " ...)");
      children(2);
    } else if (head == "<" || head == ">" || head == "<=" || head == ">=") {
      error(e.where, "numeric comparisons are not supported (only action costs are numeric)");
    } else if (head == "preference") {
      error(e.where, "preferences are not supported");
    } else {
      f.kind = Formula::Kind::atom;
      if (auto a = atom(e, "a condition")) f.atom = std::move(*a);
      else f.kind = Formula::Kind::truth;
    }
    return f;
  }

  Effect effect(const SExpr& e) {
    Effect out;
    out.where = e.where;
    if (e.is_list && e.items.empty()) return out;  // (): nothing
    if (!e.is_list || !e.items[0].is_atom()) {
      error(e.where, "expected an effect: (and ...), (not ATOM), ATOM, (forall ...), (when ...) or (increase (total-cost) N)");
      return out;
    }
    const std::string& head = e.items[0].text;
    if (head == "and") {
      for (std::size_t i = 1; i < e.items.size(); ++i) out.children.push_back(effect(e.items[i]));
    } else if (head == "not") {
      out.kind = Effect::Kind::remove;
      if (e.items.size() != 2) error(e.where, "(not ATOM) takes one atom");
      else if (auto a = atom(e.items[1], "a deleted atom")) out.atom = std::move(*a);
    } else if (head == "forall") {
      out.kind = Effect::Kind::forall;
      if (e.items.size() != 3 || !e.items[1].is_list) {
        error(e.where, "(forall (?variable - type ...) EFFECT)");
        return out;
      }
      out.variables = typed_list(e.items[1].items, 0, true, "the variables of (forall ...)");
      out.children.push_back(effect(e.items[2]));
    } else if (head == "when") {
      out.kind = Effect::Kind::when;
      if (e.items.size() != 3) {
        error(e.where, "(when CONDITION EFFECT)");
        return out;
      }
      out.condition = formula(e.items[1]);
      out.children.push_back(effect(e.items[2]));
    } else if (head == "increase") {
      out.kind = Effect::Kind::increase;
      if (e.items.size() != 3 || !e.items[1].is_form("total-cost") || e.items[1].items.size() != 1) {
        error(e.where, "only (increase (total-cost) VALUE) is supported among numeric effects");
        return out;
      }
      out.cost = cost(e.items[2]);
    } else if (head == "decrease" || head == "assign" || head == "scale-up" || head == "scale-down") {
      error(e.where, "numeric effect (" + head + " ...) is not supported; only (increase (total-cost) VALUE)");
    } else {
      out.kind = Effect::Kind::add;
      if (auto a = atom(e, "an added atom")) out.atom = std::move(*a);
      else out.kind = Effect::Kind::conjunction;
    }
    return out;
  }

  CostExpression cost(const SExpr& e) {
    CostExpression c;
    c.where = e.where;
    if (e.is_atom()) {
      try {
        std::size_t used = 0;
        const bool plain = e.text.find_first_not_of("0123456789.eE+-") == std::string::npos;
        const double value = plain ? std::stod(e.text, &used) : -1.0;
        if (!plain || used != e.text.size() || !(value >= 0) || value > 1e12) throw std::invalid_argument("");
        c.number = value;
      } catch (const std::exception&) {
        error(e.where, "a cost must be a non-negative number or a function term, not '" + e.text + "'");
      }
      return c;
    }
    if (auto a = atom(e, "a cost function term")) c.function = std::move(*a);
    return c;
  }

 protected:
  SourceText source_;
  Diagnostics diagnostics_;
};

// ------------------------------------------------------------------------------------
// Semantic checks shared by domain and problem: names, arity and types of atoms.

class Checker {
 public:
  // `declaring`: the domain being read, where a cost function used without a
  // declaration is declared by that use; null when reading a problem.
  Checker(const Domain& domain, Reader& reader, Domain* declaring = nullptr)
      : domain_(domain), reader_(reader), declaring_(declaring) {}

  using Scope = std::map<std::string, std::vector<std::string>>;  // variable -> types

  // The types of a term, or nullopt (reported) when it names nothing.
  /// The types of a term, or null (and an error) when it is undeclared.
  const std::vector<std::string>* term_types(const Term& t, const Scope& scope,
                                             const std::map<std::string, std::vector<std::string>>& objects) {
    if (t.variable) {
      auto it = scope.find(t.name);
      if (it == scope.end()) {
        reader_.error(t.where, "undeclared variable '" + t.name + "'");
        return nullptr;
      }
      return &it->second;
    }
    auto it = objects.find(t.name);
    if (it == objects.end()) {
      reader_.error(t.where, "undeclared constant or object '" + t.name + "'");
      return nullptr;
    }
    return &it->second;
  }

  bool types_overlap(const std::vector<std::string>& a, const std::vector<std::string>& b) const {
    for (const std::string& x : a) {
      for (const std::string& y : b) {
        if (domain_.is_subtype(x, y) || domain_.is_subtype(y, x)) return true;
      }
    }
    return false;
  }

  bool types_within(const std::vector<std::string>& a, const std::vector<std::string>& b) const {
    for (const std::string& x : a) {
      bool inside = false;
      for (const std::string& y : b) inside = inside || domain_.is_subtype(x, y);
      if (!inside) return false;
    }
    return true;
  }

  std::string type_text(const std::vector<std::string>& types) const {
    if (types.size() == 1) return types[0];
    std::string out = "(either";
    for (const auto& t : types) out += " " + t;
    return out + ")";
  }

  // `strict`: arguments must be of the parameter's type (problem facts); otherwise they
  // only must not be of an unrelated type (a variable of a supertype may be passed).
  void check_atom(const Atom& a, const Scope& scope, const std::map<std::string, std::vector<std::string>>& objects,
                  bool strict, bool function = false) {
    if (a.predicate == "=" && !function) {
      if (a.args.size() != 2) reader_.error(a.where, "(= a b) takes two arguments");
      for (const Term& t : a.args) term_types(t, scope, objects);
      return;
    }
    const auto& table = function ? domain_.functions : domain_.predicates;
    auto it = table.find(a.predicate);
    if (it == table.end()) {
      std::string hint;
      for (const auto& [name, decl] : table) {
        std::string x = name, y = a.predicate;
        std::erase(x, '-');
        std::erase(y, '-');
        std::erase(x, '_');
        std::erase(y, '_');
        if (x == y) hint = " (did you mean '" + name + "'?)";
      }
      reader_.error(a.where, std::string("undeclared ") + (function ? "function" : "predicate") + " '" + a.predicate +
                                 "'" + hint);
      return;
    }
    const PredicateDecl& decl = it->second;
    if (a.args.size() != decl.parameters.size()) {
      reader_.error(a.where, "'" + a.predicate + "' takes " + std::to_string(decl.parameters.size()) + " argument" +
                                 (decl.parameters.size() == 1 ? "" : "s") + ", not " + std::to_string(a.args.size()));
      return;
    }
    for (std::size_t i = 0; i < a.args.size(); ++i) {
      const auto types = term_types(a.args[i], scope, objects);
      if (!types) continue;
      const auto& wanted = decl.parameters[i].types;
      const bool ok = strict ? types_within(*types, wanted) : types_overlap(*types, wanted);
      if (!ok) {
        reader_.error(a.args[i].where, "type mismatch: '" + a.args[i].name + "' is " + type_text(*types) +
                                           ", but argument " + std::to_string(i + 1) + " of '" + a.predicate +
                                           "' is " + type_text(wanted));
      }
    }
  }

  void check_types_exist(const std::vector<TypedName>& names) {
    for (const TypedName& n : names) {
      for (const std::string& t : n.types) {
        if (t != "object" && !domain_.types.count(t)) reader_.error(n.where, "undeclared type '" + t + "'");
      }
    }
  }

  // The scope is copied only where a quantifier adds to it.
  void check_formula(const Formula& f, const Scope& scope, const std::map<std::string, std::vector<std::string>>& objects) {
    switch (f.kind) {
      case Formula::Kind::atom: check_atom(f.atom, scope, objects, false); break;
      case Formula::Kind::exists:
      case Formula::Kind::forall: {
        check_types_exist(f.variables);
        Scope inner = scope;
        for (const TypedName& v : f.variables) inner[v.name] = v.types;
        for (const Formula& c : f.children) check_formula(c, inner, objects);
        break;
      }
      default:
        for (const Formula& c : f.children) check_formula(c, scope, objects);
    }
  }

  void check_effect(const Effect& e, const Scope& scope, const std::map<std::string, std::vector<std::string>>& objects,
                    const std::set<std::string>& derived, bool nested = false) {
    switch (e.kind) {
      case Effect::Kind::add:
      case Effect::Kind::remove:
        if (e.atom.predicate == "=") reader_.error(e.atom.where, "equality cannot be an effect");
        else if (derived.count(e.atom.predicate)) reader_.error(e.atom.where, "'" + e.atom.predicate + "' is derived; actions cannot change it");
        else check_atom(e.atom, scope, objects, false);
        break;
      case Effect::Kind::forall: {
        check_types_exist(e.variables);
        Scope inner = scope;
        for (const TypedName& v : e.variables) inner[v.name] = v.types;
        for (const Effect& c : e.children) check_effect(c, inner, objects, derived, true);
        break;
      }
      case Effect::Kind::when:
        check_formula(e.condition, scope, objects);
        for (const Effect& c : e.children) check_effect(c, scope, objects, derived, true);
        break;
      case Effect::Kind::increase:
        if (nested) {
          reader_.error(e.where, "(increase (total-cost) ...) inside (when ...) or (forall ...) is not supported; "
                                 "an action's cost must not depend on the state");
        }
        if (!e.cost.number && !e.cost.function.predicate.empty()) {
          declare_by_use(e.cost.function);
          check_atom(e.cost.function, scope, objects, false, true);
        }
        break;
      case Effect::Kind::conjunction:
        for (const Effect& c : e.children) check_effect(c, scope, objects, derived, nested);
        break;
    }
  }

 private:
  // A cost function used in (increase (total-cost) ...) without a declaration: as
  // PDDLStream reads it, declared by its first use (a stream file's :function may
  // compute it), with a warning.
  void declare_by_use(const Atom& f) {
    if (!declaring_ || declaring_->functions.count(f.predicate)) return;
    PredicateDecl decl{f.predicate, {}, f.where};
    for (std::size_t i = 0; i < f.args.size(); ++i) decl.parameters.push_back({"?x" + std::to_string(i + 1), {"object"}, f.where});
    declaring_->functions[f.predicate] = decl;
    reader_.warning(f.where, "function '" + f.predicate + "' is not declared in (:functions ...); declared here by its use, with " +
                                 std::to_string(f.args.size()) + " argument(s) of any type");
  }

  const Domain& domain_;
  Reader& reader_;
  Domain* declaring_ = nullptr;
};

// ------------------------------------------------------------------------------------

class DomainReader : public Reader {
 public:
  using Reader::Reader;

  Domain read() {
    const std::vector<SExpr> top = read_sexprs(source());
    const SExpr& def = define(top, "domain");
    domain_.name = def.items[1].items[1].text;
    domain_.file = source().file;
    domain_.where = def.where;
    std::set<std::string> seen_sections;
    std::vector<const SExpr*> actions, derived;
    for (std::size_t i = 2; i < def.items.size(); ++i) {
      const SExpr& section = def.items[i];
      if (!section.is_list || section.items.empty() || !section.items[0].is_atom()) {
        error(section.where, "expected a section such as (:predicates ...) or (:action ...)");
        continue;
      }
      const std::string& key = section.items[0].text;
      if (key != ":action" && key != ":derived" && !seen_sections.insert(key).second) {
        error(section.where, "section " + key + " appears twice");
      }
      if (key == ":requirements") requirements(section);
      else if (key == ":types") types(section);
      else if (key == ":constants") domain_.constants = typed_list(section.items, 1, false, ":constants");
      else if (key == ":predicates") declarations(section, domain_.predicates, "predicate");
      else if (key == ":functions") functions(section);
      else if (key == ":action") actions.push_back(&section);
      else if (key == ":derived") derived.push_back(&section);
      else if (key == ":durative-action") error(section.where, "durative actions are not supported");
      else if (key == ":constraints") error(section.where, "state-trajectory constraints are not supported");
      else error(section.items[0].where, "unknown domain section '" + key + "'");
    }
    // (total-cost) needs no declaration, as in Fast Downward and PDDLStream's domains.
    if (!domain_.functions.count("total-cost")) domain_.functions["total-cost"] = PredicateDecl{"total-cost", {}, def.where};
    Checker checker(domain_, *this, &domain_);
    checker.check_types_exist(domain_.constants);
    for (const auto& [name, decl] : domain_.predicates) checker.check_types_exist(decl.parameters);
    for (const auto& [name, decl] : domain_.functions) checker.check_types_exist(decl.parameters);
    for (const TypedName& c : domain_.constants) objects_[c.name] = c.types;
    for (const SExpr* d : derived) declare_derived_head(*d);
    std::set<std::string> derived_names;
    for (const SExpr* d : derived) read_derived(*d, checker, derived_names);
    for (const SExpr* a : actions) read_action(*a, checker, derived_names);
    check_stratified();
    finish();
    domain_.warnings = diagnostics_.warnings();
    return std::move(domain_);  // read once: a copy would cost as much as the reading
  }

 private:
  // A derived predicate missing from :predicates is declared by its rule's head, as
  // Fast Downward's translator (and so PDDLStream) reads it, with a warning.
  void declare_derived_head(const SExpr& section) {
    if (section.items.size() < 2 || !section.items[1].is_list || section.items[1].items.empty() ||
        !section.items[1].items[0].is_atom()) {
      return;  // read_derived reports it
    }
    const SExpr& head = section.items[1];
    if (domain_.predicates.count(head.items[0].text)) return;
    Diagnostics quiet;  // the head's own errors are read_derived's to report
    std::swap(quiet, diagnostics_);
    PredicateDecl decl{head.items[0].text, typed_list(head.items, 1, true, "the head of (:derived ...)"), head.where};
    std::swap(quiet, diagnostics_);
    if (!quiet.empty()) return;
    domain_.predicates[decl.name] = decl;
    warning(head.where, "derived predicate '" + decl.name + "' is not declared in :predicates; declared here by its rule");
  }

  void requirements(const SExpr& section) {
    for (std::size_t i = 1; i < section.items.size(); ++i) {
      const SExpr& r = section.items[i];
      if (!r.is_atom() || r.text[0] != ':') {
        error(r.where, "expected a requirement such as :strips");
        continue;
      }
      if (auto refused = kRefused.find(r.text); refused != kRefused.end()) {
        error(r.where, "unsupported requirement " + r.text + ": " + refused->second);
      } else if (!kSupported.count(r.text)) {
        error(r.where, "unknown requirement " + r.text);
      }
      domain_.requirements.insert(r.text);
    }
  }

  void types(const SExpr& section) {
    for (const TypedName& t : typed_list(section.items, 1, false, ":types", true)) {
      if (t.name == "object") continue;
      if (const auto first = type_where_.find(t.name); first != type_where_.end() && domain_.types.count(t.name)) {
        // IPC storage declares "area - object" and later "area - surface"; the last
        // declaration holds, as in Fast Downward.
        warning(t.where, "type '" + t.name + "' is declared again (first at line " + std::to_string(first->second.line) +
                             "); this declaration's parent " + join_types(t.types) + " replaces " +
                             join_types(domain_.types[t.name]));
      } else {
        type_where_[t.name] = t.where;
      }
      domain_.types[t.name] = t.types;
    }
    // A type named only as a parent is declared by that use, below object (as in IPC domains).
    std::vector<std::pair<std::string, SourceLocation>> implicit;
    for (const auto& [name, parents] : domain_.types) {
      for (const std::string& p : parents) {
        if (p != "object" && !domain_.types.count(p)) implicit.emplace_back(p, type_where_[name]);
      }
    }
    for (const auto& [name, where] : implicit) {
      domain_.types[name] = {"object"};
      type_where_.emplace(name, where);
    }
    for (const auto& [name, parents] : domain_.types) {
      // A cycle makes a type its own ancestor.
      std::set<std::string> visited;
      std::vector<std::string> open = parents;
      while (!open.empty()) {
        const std::string t = open.back();
        open.pop_back();
        if (t == name) {
          error(type_where_[name], "type '" + name + "' is its own ancestor");
          break;
        }
        if (!visited.insert(t).second) continue;
        auto it = domain_.types.find(t);
        if (it != domain_.types.end()) open.insert(open.end(), it->second.begin(), it->second.end());
      }
    }
  }

  void declarations(const SExpr& section, std::map<std::string, PredicateDecl>& table, const char* what) {
    for (std::size_t i = 1; i < section.items.size(); ++i) {
      const SExpr& d = section.items[i];
      if (!d.is_list || d.items.empty() || !d.items[0].is_atom() || d.items[0].text[0] == '?') {
        error(d.where, std::string("expected a ") + what + " declaration (name ?param - type ...)");
        continue;
      }
      PredicateDecl decl{d.items[0].text,
                         typed_list(d.items, 1, true, std::string("the ") + what + " '" + d.items[0].text + "'", true),
                         d.where};
      if (decl.name == "=") error(d.where, "'=' is built in and cannot be declared");
      if (const auto first = table.find(decl.name); first != table.end()) {
        // PDDLStream's own domains repeat a declaration; the same arity is harmless.
        const std::string again = std::string(what) + " '" + decl.name + "' is declared twice (first at line " +
                                  std::to_string(first->second.where.line) + ")";
        if (first->second.parameters.size() != decl.parameters.size()) {
          error(d.where, again + " with " + std::to_string(first->second.parameters.size()) + " and " +
                             std::to_string(decl.parameters.size()) + " parameters");
        } else {
          warning(d.where, again + "; the first declaration is kept");
        }
        continue;
      }
      table[decl.name] = decl;
    }
  }

  void functions(const SExpr& section) {
    // (f ?a - t) - number  ...: skip the "- number" after each declaration.
    SExpr cleaned = section;
    cleaned.items.clear();
    cleaned.items.push_back(section.items[0]);
    for (std::size_t i = 1; i < section.items.size(); ++i) {
      const SExpr& item = section.items[i];
      if (item.is("-")) {
        if (i + 1 < section.items.size() && section.items[i + 1].is("number")) ++i;
        else error(item.where, "function types other than 'number' are not supported");
        continue;
      }
      cleaned.items.push_back(item);
    }
    declarations(cleaned, domain_.functions, "function");
  }

  void read_action(const SExpr& section, Checker& checker, const std::set<std::string>& derived) {
    Action action;
    action.where = section.where;
    if (section.items.size() < 2 || !section.items[1].is_atom()) {
      error(section.where, "expected (:action NAME :parameters (...) :precondition ... :effect ...)");
      return;
    }
    action.name = section.items[1].text;
    if (domain_.find_action(action.name)) error(section.items[1].where, "action '" + action.name + "' is declared twice");
    bool has_effect = false;
    std::set<std::string> keys;
    for (std::size_t i = 2; i < section.items.size(); i += 2) {
      const SExpr& key = section.items[i];
      if (!key.is_atom() || key.text[0] != ':' || i + 1 >= section.items.size()) {
        error(key.where, "expected :parameters, :precondition or :effect followed by its value");
        break;
      }
      if (!keys.insert(key.text).second) error(key.where, key.text + " appears twice in action '" + action.name + "'");
      const SExpr& value = section.items[i + 1];
      if (key.text == ":parameters") {
        if (!value.is_list) error(value.where, ":parameters takes a list (?p - type ...)");
        else action.parameters = typed_list(value.items, 0, true, "the parameters of '" + action.name + "'");
      } else if (key.text == ":precondition") {
        action.precondition = formula(value);
      } else if (key.text == ":effect") {
        action.effect = effect(value);
        has_effect = true;
      } else {
        error(key.where, "unknown action keyword '" + key.text + "'");
      }
    }
    if (!has_effect) error(section.where, "action '" + action.name + "' has no :effect");
    Checker::Scope scope;
    checker.check_types_exist(action.parameters);
    for (const TypedName& p : action.parameters) scope[p.name] = p.types;
    checker.check_formula(action.precondition, scope, objects_);
    checker.check_effect(action.effect, scope, objects_, derived);
    domain_.actions.push_back(std::move(action));
  }

  void read_derived(const SExpr& section, Checker& checker, std::set<std::string>& derived) {
    if (section.items.size() != 3 || !section.items[1].is_list || section.items[1].items.empty() ||
        !section.items[1].items[0].is_atom()) {
      error(section.where, "expected (:derived (predicate ?x ...) CONDITION)");
      return;
    }
    const SExpr& head = section.items[1];
    DerivedRule rule;
    rule.where = section.where;
    rule.head.name = head.items[0].text;
    rule.head.where = head.where;
    rule.head.parameters = typed_list(head.items, 1, true, "the head of (:derived ...)");
    auto decl = domain_.predicates.find(rule.head.name);
    if (decl == domain_.predicates.end()) {
      error(head.where, "derived predicate '" + rule.head.name + "' is not declared in :predicates");
      return;
    }
    if (decl->second.parameters.size() != rule.head.parameters.size()) {
      error(head.where, "'" + rule.head.name + "' takes " + std::to_string(decl->second.parameters.size()) + " arguments");
      return;
    }
    // Untyped head variables take the declared types.
    for (std::size_t i = 0; i < rule.head.parameters.size(); ++i) {
      if (rule.head.parameters[i].types == std::vector<std::string>{"object"}) {
        rule.head.parameters[i].types = decl->second.parameters[i].types;
      }
    }
    rule.body = formula(section.items[2]);
    Checker::Scope scope;
    for (const TypedName& p : rule.head.parameters) scope[p.name] = p.types;
    checker.check_formula(rule.body, scope, objects_);
    derived.insert(rule.head.name);
    domain_.derived.push_back(std::move(rule));
  }

  // Derived predicates must not depend on their own negation (through other rules).
  void check_stratified() {
    std::map<std::string, int> stratum;
    for (const DerivedRule& r : domain_.derived) stratum[r.head.name] = 0;
    std::function<void(const Formula&, bool, std::vector<std::pair<std::string, bool>>&)> uses =
        [&](const Formula& f, bool negated, std::vector<std::pair<std::string, bool>>& out) {
          if (f.kind == Formula::Kind::atom && stratum.count(f.atom.predicate)) out.push_back({f.atom.predicate, negated});
          for (std::size_t i = 0; i < f.children.size(); ++i) {
            const bool flips = f.kind == Formula::Kind::negation || (f.kind == Formula::Kind::implication && i == 0);
            uses(f.children[i], negated != flips, out);
          }
        };
    const int limit = static_cast<int>(stratum.size()) + 1;
    for (int round = 0; round <= limit; ++round) {
      bool changed = false;
      for (const DerivedRule& r : domain_.derived) {
        std::vector<std::pair<std::string, bool>> body;
        uses(r.body, false, body);
        for (const auto& [p, negated] : body) {
          const int need = stratum[p] + (negated ? 1 : 0);
          if (stratum[r.head.name] < need) {
            stratum[r.head.name] = need;
            changed = true;
            if (need > limit) {
              error(r.where, "derived predicate '" + r.head.name + "' depends on its own negation (not stratified)");
              return;
            }
          }
        }
      }
      if (!changed) return;
    }
  }

  Domain domain_;
  std::map<std::string, SourceLocation> type_where_;
  std::map<std::string, std::vector<std::string>> objects_;  // constants and their types
};

class ProblemReader : public Reader {
 public:
  ProblemReader(SourceText source, const Domain& domain) : Reader(std::move(source)), domain_(domain) {}

  Problem read() {
    const std::vector<SExpr> top = read_sexprs(source());
    const SExpr& def = define(top, "problem");
    problem_.name = def.items[1].items[1].text;
    problem_.file = source().file;
    problem_.where = def.where;
    for (const TypedName& c : domain_.constants) objects_[c.name] = c.types;
    std::set<std::string> seen;
    const SExpr* init = nullptr;
    const SExpr* goal = nullptr;
    for (std::size_t i = 2; i < def.items.size(); ++i) {
      const SExpr& section = def.items[i];
      if (!section.is_list || section.items.empty() || !section.items[0].is_atom()) {
        error(section.where, "expected a section such as (:objects ...) or (:init ...)");
        continue;
      }
      const std::string& key = section.items[0].text;
      if (!seen.insert(key).second) error(section.where, "section " + key + " appears twice");
      if (key == ":domain") {
        if (section.items.size() != 2 || !section.items[1].is_atom()) error(section.where, "expected (:domain NAME)");
        else problem_.domain_name = section.items[1].text;
        if (!problem_.domain_name.empty() && problem_.domain_name != domain_.name) {
          error(section.items[1].where, "the problem is for domain '" + problem_.domain_name + "', but the domain is '" +
                                            domain_.name + "'");
        }
      } else if (key == ":requirements") {
        // Accepted; the domain's requirements rule.
      } else if (key == ":objects") {
        problem_.objects = typed_list(section.items, 1, false, ":objects");
      } else if (key == ":init") {
        init = &section;
      } else if (key == ":goal") {
        if (section.items.size() != 2) error(section.where, "expected (:goal CONDITION)");
        else goal = &section.items[1];
      } else if (key == ":metric") {
        metric(section);
      } else {
        error(section.items[0].where, "unsupported problem section '" + key + "'");
      }
    }
    if (problem_.domain_name.empty()) error(def.where, "the problem has no (:domain NAME)");
    Checker checker(domain_, *this);
    checker.check_types_exist(problem_.objects);
    std::vector<TypedName> objects;
    std::unordered_map<std::string_view, const TypedName*> constants;
    for (const TypedName& c : domain_.constants) constants.emplace(c.name, &c);
    for (const TypedName& o : problem_.objects) {
      const auto found = constants.find(o.name);
      if (found != constants.end()) {
        const TypedName* constant = found->second;
        // Repeating a constant with its own type is harmless (IPC files do it); another type is not.
        if (constant->types != o.types) error(o.where, "object '" + o.name + "' is a constant of the domain with another type");
        continue;
      }
      objects_[o.name] = o.types;
      objects.push_back(o);
    }
    problem_.objects = objects;
    if (init) read_init(*init, checker);
    else error(def.where, "the problem has no (:init ...); write (:init) for an empty initial state");
    if (!goal) {
      error(def.where, "the problem has no (:goal ...)");
    } else {
      problem_.goal = formula(*goal);
      checker.check_formula(problem_.goal, {}, objects_);
    }
    finish();
    return std::move(problem_);
  }

 private:
  void metric(const SExpr& section) {
    if (section.items.size() == 3 && section.items[1].is("minimize") && section.items[2].is_form("total-cost") &&
        section.items[2].items.size() == 1) {
      problem_.minimize_total_cost = true;
    } else {
      error(section.where, "only (:metric minimize (total-cost)) is supported");
    }
  }

  void read_init(const SExpr& section, Checker& checker) {
    const std::set<std::string> derived = [&] {
      std::set<std::string> names;
      for (const DerivedRule& r : domain_.derived) names.insert(r.head.name);
      return names;
    }();
    for (std::size_t i = 1; i < section.items.size(); ++i) {
      const SExpr& fact = section.items[i];
      if (fact.is_form("=")) {
        if (fact.items.size() != 3) {
          error(fact.where, "expected (= (function args) NUMBER)");
          continue;
        }
        auto function = atom(fact.items[1], "a function term");
        const CostExpression value = cost(fact.items[2]);
        if (!function || !value.number) continue;
        checker.check_atom(*function, {}, objects_, true, true);
        problem_.numeric_init.push_back({*function, *value.number});
        continue;
      }
      if (fact.is_form("not")) continue;  // closed world: false anyway
      if (fact.is_form("at") && fact.items.size() == 3 && fact.items[1].is_atom() && fact.items[2].is_list) {
        error(fact.where, "timed initial literal (at " + fact.items[1].text +
                              " ...): timed initial literals (PDDL 2.2, :timed-initial-literals) are not supported");
        continue;
      }
      auto a = atom(fact, "an initial fact");
      if (!a) continue;
      for (const Term& t : a->args) {
        if (t.variable) error(t.where, "initial facts cannot contain variables");
      }
      if (derived.count(a->predicate)) error(a->where, "'" + a->predicate + "' is derived and cannot be an initial fact");
      checker.check_atom(*a, {}, objects_, true);
      problem_.init.push_back(std::move(*a));
    }
  }

  const Domain& domain_;
  Problem problem_;
  std::map<std::string, std::vector<std::string>> objects_;
};

}  // namespace

const std::set<std::string>& supported_requirements() { return kSupported; }

const Action* Domain::find_action(const std::string& action) const {
  for (const Action& a : actions) {
    if (a.name == action) return &a;
  }
  return nullptr;
}

bool Domain::is_subtype(const std::string& type, const std::string& ancestor) const {
  if (type == ancestor || ancestor == "object") return true;
  std::vector<std::string> open{type};
  std::set<std::string> visited;
  while (!open.empty()) {
    const std::string t = open.back();
    open.pop_back();
    if (t == ancestor) return true;
    if (!visited.insert(t).second) continue;
    auto it = types.find(t);
    if (it != types.end()) open.insert(open.end(), it->second.begin(), it->second.end());
  }
  return false;
}

Domain parse_domain(const std::string& text, const std::string& file) { return DomainReader({file, text}).read(); }

Domain load_domain(const std::filesystem::path& file) { return parse_domain(read_text_file(file), file.string()); }

Problem parse_problem(const std::string& text, const std::string& file, const Domain& domain) {
  return ProblemReader({file, text}, domain).read();
}

Problem load_problem(const std::filesystem::path& file, const Domain& domain) {
  return parse_problem(read_text_file(file), file.string(), domain);
}

std::string to_string(const Atom& atom) {
  std::string out = "(" + atom.predicate;
  for (const Term& t : atom.args) out += " " + t.name;
  return out + ")";
}

}  // namespace cluttertamp::pddl
