#include "cluttertamp/stream/stream_file.hpp"

#include <algorithm>
#include <cctype>
#include <map>

#include "cluttertamp/pddl/parser.hpp"
#include "cluttertamp/pddl/sexpr.hpp"
#include "cluttertamp/pddl/read_atom.hpp"

namespace cluttertamp::stream {

namespace {

using pddl::Atom;
using pddl::SExpr;
using pddl::Term;

// PDDLStream forms we know and do not run, with why.
const std::map<std::string, std::string> kRefused = {
    {":optimizer", "optimizers (PDDLStream's :optimizer) are not supported"},
    {":wild-stream", "wild streams (certifying facts beyond :certified) are not supported"},
    {":wild", "wild streams (certifying facts beyond :certified) are not supported"},
    {":gen-fn", "write (:stream ...) with :outputs instead of :gen-fn"},
};

bool contains(const std::vector<Term>& terms, const std::string& name) {
  return std::any_of(terms.begin(), terms.end(), [&](const Term& t) { return t.name == name; });
}

class StreamReader {
 public:
  StreamReader(pddl::SourceText source, const pddl::Domain* domain) : source_(std::move(source)), domain_(domain) {
    if (domain_) {
      changed_ = changed_predicates(*domain_);
      for (const pddl::DerivedRule& r : domain_->derived) derived_.insert(r.head.name);
    }
  }

  StreamFile read() {
    const std::vector<SExpr> top = pddl::read_sexprs(source_);
    if (top.empty()) source_.fail({source_.file, 1, 1}, "empty file: expected (define (stream NAME) ...)");
    if (top.size() > 1) error(top[1].where, "text after the end of the (define ...)");
    const SExpr& def = top[0];
    if (!def.is_form("define") || def.items.size() < 2 || !def.items[1].is_form("stream") ||
        def.items[1].items.size() != 2 || !def.items[1].items[1].is_atom()) {
      source_.fail(def.where, "expected (define (stream NAME) ...)");
    }
    file_.name = def.items[1].items[1].text;
    file_.file = source_.file;
    file_.where = def.where;
    for (std::size_t i = 2; i < def.items.size(); ++i) declaration(def.items[i]);
    diagnostics_.throw_if_any();
    file_.warnings = diagnostics_.warnings();
    return file_;
  }

 private:
  void error(const SourceLocation& where, const std::string& message) {
    diagnostics_.error(where, source_.with_excerpt(where, message));
  }
  void warning(const SourceLocation& where, const std::string& message) {
    diagnostics_.warning(where, source_.with_excerpt(where, message));
  }

  void declaration(const SExpr& e) {
    if (!e.is_list || e.items.empty() || !e.items[0].is_atom()) {
      error(e.where, "expected (:stream ...), (:predicate ...), (:function ...) or (:rule ...)");
      return;
    }
    const std::string& head = e.items[0].text;
    if (head == ":stream") return stream(e);
    if (head == ":rule") return rule(e);
    if (head == ":predicate" || head == ":function") return test_or_function(e, head == ":function");
    if (const auto it = kRefused.find(head); it != kRefused.end()) return error(e.where, it->second);
    error(e.items[0].where, "unknown declaration '" + head + "': expected :stream, :predicate, :function or :rule");
  }

  // :keyword value pairs after `first`, each keyword once, only those in `allowed`.
  std::map<std::string, const SExpr*> keywords(const SExpr& e, std::size_t first, const std::vector<std::string>& allowed,
                                               const std::string& what) {
    std::map<std::string, const SExpr*> out;
    for (std::size_t i = first; i < e.items.size(); i += 2) {
      const SExpr& key = e.items[i];
      if (!key.is_atom() || key.text.empty() || key.text[0] != ':') {
        error(key.where, "expected a :keyword in " + what);
        return out;
      }
      if (std::find(allowed.begin(), allowed.end(), key.text) == allowed.end()) {
        std::string list;
        for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
        error(key.where, "unknown keyword '" + key.text + "' in " + what + " (expected " + list + ")");
        continue;
      }
      if (i + 1 >= e.items.size()) {
        error(key.where, "'" + key.text + "' without a value in " + what);
        break;
      }
      if (!out.emplace(key.text, &e.items[i + 1]).second) error(key.where, "'" + key.text + "' appears twice in " + what);
    }
    return out;
  }

  static const SExpr* value(const std::map<std::string, const SExpr*>& k, const std::string& key) {
    const auto it = k.find(key);
    return it == k.end() ? nullptr : it->second;
  }

  std::vector<Term> variables(const SExpr* e, const std::string& what) {
    std::vector<Term> out;
    if (!e) return out;
    if (!e->is_list) {
      error(e->where, "expected a list of ?variables for " + what);
      return out;
    }
    for (const SExpr& item : e->items) {
      if (!item.is_atom() || item.text.size() < 2 || item.text[0] != '?') {
        error(item.where, "expected a ?variable in " + what);
        continue;
      }
      if (contains(out, item.text)) error(item.where, "'" + item.text + "' appears twice in " + what);
      else out.push_back({item.text, true, item.where});
    }
    return out;
  }

  // An atom, (and ATOM...) or (): the facts of :domain or :certified.
  std::vector<Atom> conjunction(const SExpr* e, const std::string& what) {
    std::vector<Atom> out;
    if (!e || (e->is_list && e->items.empty())) return out;
    if (e->is_form("and")) {
      for (std::size_t i = 1; i < e->items.size(); ++i) {
        if (auto a = atom(e->items[i], what)) out.push_back(*a);
      }
    } else if (auto a = atom(*e, what)) {
      out.push_back(*a);
    }
    return out;
  }

  std::optional<Atom> atom(const SExpr& e, const std::string& what) {
    if (e.is_form("not") || e.is_form("or") || e.is_form("exists") || e.is_form("forall") || e.is_form("imply")) {
      error(e.where, what + " must be a conjunction of atoms, not (" + e.items[0].text + " ...)");
      return std::nullopt;
    }
    pddl::NotAnAtom why{};
    SourceLocation where;
    auto a = pddl::read_atom(e, why, where);
    if (!a && why == pddl::NotAnAtom::head) error(where, "expected an atom (predicate arg...) in " + what);
    if (!a && why == pddl::NotAnAtom::argument) error(where, "arguments must be names or ?variables in " + what);
    return a;
  }

  void stream(const SExpr& e) {
    StreamDecl s;
    s.kind = StreamDecl::Kind::stream;
    s.where = e.where;
    if (e.items.size() < 2 || !e.items[1].is_atom() || e.items[1].text[0] == ':' || e.items[1].text[0] == '?') {
      error(e.where, "expected (:stream NAME :inputs (...) :domain ... :outputs (...) :certified ...)");
      return;
    }
    s.name = e.items[1].text;
    // A name as PDDL writes names (a problem file binds it under `streams:`, a stream map by it).
    const bool named = std::isalpha(static_cast<unsigned char>(s.name[0])) &&
                       std::all_of(s.name.begin(), s.name.end(), [](char c) {
                         return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_';
                       });
    if (!named) error(e.items[1].where, "stream name '" + s.name + "' is not a name: a letter, then letters, digits, '-' or '_'");
    const std::string what = "stream '" + s.name + "'";
    const auto k = keywords(e, 2, {":inputs", ":domain", ":outputs", ":certified", ":fluents"}, what);
    s.inputs = variables(value(k, ":inputs"), ":inputs of " + what);
    s.domain = conjunction(value(k, ":domain"), ":domain of " + what);
    s.outputs = variables(value(k, ":outputs"), ":outputs of " + what);
    s.certified = conjunction(value(k, ":certified"), ":certified of " + what);
    if (const SExpr* f = value(k, ":fluents")) fluents(*f, s, what);
    if (!k.count(":certified")) error(e.where, what + " has no :certified facts");
    for (const Term& o : s.outputs) {
      if (contains(s.inputs, o.name)) error(o.where, "'" + o.name + "' is both an input and an output of " + what);
    }
    check_variables(s, what);
    add(std::move(s));
  }

  void rule(const SExpr& e) {
    StreamDecl s;
    s.kind = StreamDecl::Kind::rule;
    s.where = e.where;
    s.name = "rule@" + std::to_string(e.where.line);
    const std::string what = "the rule at line " + std::to_string(e.where.line);
    const auto k = keywords(e, 1, {":inputs", ":domain", ":certified"}, what);
    s.inputs = variables(value(k, ":inputs"), ":inputs of " + what);
    s.domain = conjunction(value(k, ":domain"), ":domain of " + what);
    s.certified = conjunction(value(k, ":certified"), ":certified of " + what);
    if (!k.count(":certified")) error(e.where, what + " has no :certified facts");
    check_variables(s, what);
    add(std::move(s));
  }

  void test_or_function(const SExpr& e, bool function) {
    StreamDecl s;
    s.kind = function ? StreamDecl::Kind::function : StreamDecl::Kind::predicate;
    s.where = e.where;
    const char* form = function ? "(:function (F ?x...) DOMAIN)" : "(:predicate (P ?x...) DOMAIN)";
    if (e.items.size() < 2 || e.items.size() > 3) {
      error(e.where, std::string("expected ") + form);
      return;
    }
    auto head = atom(e.items[1], std::string("the head of ") + form);
    if (!head) return;
    s.head = *head;
    s.name = head->predicate;
    const std::string what = std::string(function ? "function" : "predicate") + " '" + s.name + "'";
    for (const Term& t : head->args) {
      if (!t.variable) error(t.where, "the head of " + what + " takes ?variables only");
      else if (contains(s.inputs, t.name)) error(t.where, "'" + t.name + "' appears twice in the head of " + what);
      else s.inputs.push_back(t);
    }
    if (e.items.size() == 3) s.domain = conjunction(&e.items[2], "the domain of " + what);
    if (!function) s.certified.push_back(s.head);
    check_variables(s, what);
    if (function && domain_) {
      const auto f = domain_->functions.find(s.name);
      if (f == domain_->functions.end()) {
        // PDDLStream lets the stream file declare it; the domain then has no use for it.
        warning(head->where, what + " is not declared in (:functions ...) of domain '" + domain_->name +
                                 "', which never uses it: its values will not count");
      } else if (f->second.parameters.size() != head->args.size()) {
        error(head->where, what + " takes " + std::to_string(f->second.parameters.size()) + " argument(s) in domain '" +
                               domain_->name + "'");
      }
    }
    add(std::move(s));
  }

  void fluents(const SExpr& e, StreamDecl& s, const std::string& what) {
    if (!e.is_list) {
      error(e.where, "expected a list of predicate names for :fluents of " + what);
      return;
    }
    for (const SExpr& item : e.items) {
      if (!item.is_atom() || item.text[0] == '?' || item.text[0] == ':') {
        error(item.where, "expected a predicate name in :fluents of " + what);
        continue;
      }
      if (domain_ && !domain_->predicates.count(item.text)) {
        error(item.where, "'" + item.text + "' in :fluents of " + what + " is not a predicate of domain '" + domain_->name + "'");
      } else if (domain_ && !changed_.count(item.text)) {
        error(item.where, "'" + item.text + "' in :fluents of " + what + " is never changed by an action: not a fluent");
      }
      s.fluents.push_back(item.text);
    }
  }

  // Domain variables are inputs, certified variables inputs or outputs; with a domain,
  // every atom is declared, of the right arity and static.
  void check_variables(const StreamDecl& s, const std::string& what) {
    for (const Atom& a : s.domain) {
      for (const Term& t : a.args) {
        if (t.variable && !contains(s.inputs, t.name)) {
          error(t.where, "'" + t.name + "' in :domain of " + what + " is not an input");
        }
      }
      check_atom(a, ":domain of " + what);
    }
    for (const Atom& a : s.certified) {
      for (const Term& t : a.args) {
        if (t.variable && !contains(s.inputs, t.name) && !contains(s.outputs, t.name)) {
          error(t.where, "'" + t.name + "' in :certified of " + what + " is neither an input nor an output");
        }
      }
      check_atom(a, ":certified of " + what);
    }
  }

  void check_atom(const Atom& a, const std::string& what) {
    if (!domain_) return;
    const auto p = domain_->predicates.find(a.predicate);
    if (p == domain_->predicates.end()) return;  // a predicate of the streams only (as PDDLStream allows)
    if (p->second.parameters.size() != a.args.size()) {
      error(a.where, "'" + a.predicate + "' takes " + std::to_string(p->second.parameters.size()) + " argument(s), not " +
                         std::to_string(a.args.size()));
    }
    if (changed_.count(a.predicate)) {
      // PDDLStream makes such a stream exogenous (its facts observed in the state, not
      // certified once); the searches here certify static facts only.
      error(a.where, "'" + a.predicate + "' in " + what + " is changed by actions: PDDLStream treats such a stream as "
                                                           "exogenous, which is not supported (streams certify static "
                                                           "facts; a stream may read fluents through :fluents)");
    } else if (derived_.count(a.predicate)) {
      error(a.where, "'" + a.predicate + "' in " + what + " is derived; streams work on static facts only");
    }
  }

  void add(StreamDecl s) {
    if (s.kind != StreamDecl::Kind::rule) {
      for (const StreamDecl& other : file_.streams) {
        if (other.name == s.name && other.kind != StreamDecl::Kind::rule) {
          error(s.where, "'" + s.name + "' is declared twice (first at line " + std::to_string(other.where.line) + ")");
          return;
        }
      }
    }
    file_.streams.push_back(std::move(s));
  }

  pddl::SourceText source_;
  const pddl::Domain* domain_;
  std::set<std::string> changed_, derived_;
  Diagnostics diagnostics_;
  StreamFile file_;
};

void collect_changed(const pddl::Effect& e, std::set<std::string>& out) {
  if (e.kind == pddl::Effect::Kind::add || e.kind == pddl::Effect::Kind::remove) out.insert(e.atom.predicate);
  for (const pddl::Effect& c : e.children) collect_changed(c, out);
}

}  // namespace

const StreamDecl* StreamFile::find(const std::string& stream) const {
  for (const StreamDecl& s : streams) {
    if (s.name == stream) return &s;
  }
  return nullptr;
}

std::set<std::string> changed_predicates(const pddl::Domain& domain) {
  std::set<std::string> out;
  for (const pddl::Action& a : domain.actions) collect_changed(a.effect, out);
  return out;
}

StreamFile parse_stream_file(const std::string& text, const std::string& file, const pddl::Domain* domain) {
  return StreamReader({file, text}, domain).read();
}

StreamFile load_stream_file(const std::filesystem::path& file, const pddl::Domain* domain) {
  return parse_stream_file(pddl::read_text_file(file), file.string(), domain);
}

}  // namespace cluttertamp::stream
