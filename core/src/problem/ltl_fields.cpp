#include "ltl_fields.hpp"

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "field_text.hpp"
#include "marsyn/core/problem/input_limits.hpp"
#include "stage_fields.hpp"

namespace marsyn::loader {

namespace {

// The words a formula gives a meaning of its own: they cannot name regions.
const std::vector<std::string> kReserved = {"F", "G", "X", "U", "R", "W", "M", "V", "true", "false", "goal", "obstacles"};

const char* kFragment = "the LTL form supports F, G, !, &, parentheses and names: F(a & F(b & F goal)) & G !obstacle";

// Deep enough for 1000 stages (read_stages' limit: two levels per stage), shallow enough for the stack.
constexpr int kMaxDepth = 2100;

struct Node {
  enum Kind { And, Fin, Glob, Not, Name } kind;
  int col = 0;
  std::string name;
  std::vector<Node> kids;
};

struct Token {
  enum Kind { LParen, RParen, And, Not, Fin, Glob, Name, End } kind;
  int col = 0;
  std::string text;
};

class Parser {
 public:
  Parser(const Field& f, std::string text) : f_(f), s_(std::move(text)) { lex(); }

  Node formula() {
    Node n = conj(0);
    if (tok().kind != Token::End)
      fail(tok().col, "unexpected '" + tok().text + "'", "the formula before it is complete (a ')' without its '(', or a missing '&'?)");
    return n;
  }

  // "WHAT at column C of the formula "...": WHY"
  [[noreturn]] void fail(int col, const std::string& what, const std::string& why = "") const {
    f_.fail(what + " at column " + std::to_string(col) + " of the formula \"" + s_ + "\"" + (why.empty() ? "" : "; " + why));
  }

 private:
  static bool name_char(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.';
  }

  [[noreturn]] void unsupported(int col, const std::string& op, const std::string& meaning) const {
    fail(col, "unsupported operator '" + op + "' (" + meaning + ")", kFragment);
  }

  // Every operator outside the fragment is rejected here, by name, before any structure is read.
  void lex() {
    const std::size_t N = s_.size();
    std::size_t i = 0;
    auto starts = [&](const char* w) { return s_.compare(i, std::char_traits<char>::length(w), w) == 0; };
    while (i < N) {
      const int col = static_cast<int>(i) + 1;
      const char c = s_[i];
      if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
        ++i;
        continue;
      }
      if (starts("<->") || starts("<=>")) unsupported(col, s_.substr(i, 3), "equivalence");
      if (starts("->") || starts("=>")) unsupported(col, s_.substr(i, 2), "implication");
      if (starts("[]")) unsupported(col, "[]", "always in Spin's syntax; write G");
      if (starts("<>")) unsupported(col, "<>", "eventually in Spin's syntax; write F");
      if (starts("||") || starts("\\/")) unsupported(col, s_.substr(i, 2), "disjunction");
      if (c == '|') unsupported(col, "|", "disjunction");
      if (c == '^') unsupported(col, "^", "exclusive or");
      if (starts("&&") || starts("/\\")) {
        toks_.push_back({Token::And, col, s_.substr(i, 2)});
        i += 2;
        continue;
      }
      if (c == '&' || c == '!' || c == '(' || c == ')') {
        toks_.push_back({c == '&' ? Token::And : c == '!' ? Token::Not : c == '(' ? Token::LParen : Token::RParen, col,
                         std::string(1, c)});
        ++i;
        continue;
      }
      if (!name_char(c)) fail(col, "unexpected character '" + printable(std::string(1, c)) + "'", kFragment);
      std::size_t j = i;
      // '-' belongs to names (shelf-a) unless it starts "->".
      while (j < N && name_char(s_[j]) && !(s_[j] == '-' && j + 1 < N && s_[j + 1] == '>')) ++j;
      const std::string w = s_.substr(i, j - i);
      i = j;
      if (w == "F") toks_.push_back({Token::Fin, col, w});
      else if (w == "G") toks_.push_back({Token::Glob, col, w});
      else if (w == "U") unsupported(col, w, "until");
      else if (w == "X") unsupported(col, w, "next");
      else if (w == "R" || w == "V") unsupported(col, w, "release");
      else if (w == "W") unsupported(col, w, "weak until");
      else if (w == "M") unsupported(col, w, "strong release");
      else if (w == "true" || w == "false" || w == "1" || w == "0")
        fail(col, "unsupported constant '" + w + "'", kFragment);
      else toks_.push_back({Token::Name, col, w});
    }
    toks_.push_back({Token::End, static_cast<int>(N) + 1, "end of the formula"});
  }

  const Token& tok() const { return toks_[pos_]; }

  Node conj(int depth) {
    Node first = unary(depth);
    if (tok().kind != Token::And) return first;
    Node n{Node::And, first.col, {}, {}};
    n.kids.push_back(std::move(first));
    while (tok().kind == Token::And) {
      ++pos_;
      n.kids.push_back(unary(depth));
    }
    return n;
  }

  Node unary(int depth) {
    if (depth > kMaxDepth) fail(tok().col, "the formula is nested more than " + std::to_string(kMaxDepth) + " deep");
    const Token t = tok();
    switch (t.kind) {
      case Token::Fin:
      case Token::Glob:
      case Token::Not: {
        ++pos_;
        Node n{t.kind == Token::Fin ? Node::Fin : t.kind == Token::Glob ? Node::Glob : Node::Not, t.col, {}, {}};
        n.kids.push_back(unary(depth + 1));
        return n;
      }
      case Token::LParen: {
        ++pos_;
        Node n = conj(depth + 1);
        if (tok().kind != Token::RParen)
          fail(tok().col, "expected ')' to close the '(' at column " + std::to_string(t.col) + ", got '" + tok().text + "'");
        ++pos_;
        return n;
      }
      case Token::Name:
        ++pos_;
        return Node{Node::Name, t.col, t.text, {}};
      default:
        fail(t.col, "expected a name, F, G, ! or '(', got '" + t.text + "'");
    }
  }

  const Field& f_;
  std::string s_;
  std::vector<Token> toks_;
  std::size_t pos_ = 0;
};

void flatten(const Node& n, std::vector<const Node*>& out) {
  if (n.kind != Node::And) {
    out.push_back(&n);
    return;
  }
  for (const auto& k : n.kids) flatten(k, out);
}

std::string describe(const Node& n) {
  switch (n.kind) {
    case Node::Fin: return "F";
    case Node::Glob: return "G";
    case Node::Not: return "'!'";
    case Node::Name: return "'" + n.name + "'";
    default: return "a conjunction (&)";
  }
}

// The F chain F(a & F(b & F goal)): the region names in visiting order, with their columns.
void read_chain(const Parser& p, const Node& fin, std::vector<std::pair<std::string, int>>& visits) {
  const Node* f = &fin;
  for (;;) {
    std::vector<const Node*> kids;
    flatten(f->kids[0], kids);
    if (kids.size() == 1) {
      const Node& k = *kids[0];
      if (k.kind == Node::Name && k.name == "goal") return;
      if (k.kind == Node::Name)
        p.fail(k.col, "the chain of F ends in 'F " + k.name + "', not 'F goal'",
               "the agent's goal is the last stage and the innermost F: write F(" + k.name + " & F goal)");
      p.fail(k.col, "unsupported " + describe(k) + " directly under an F",
             "each F holds one region and the rest of the mission, F(a & F(...)), the last one F goal");
    }
    const Node* name = nullptr;
    const Node* next = nullptr;
    for (const Node* k : kids) {
      if (k->kind == Node::Name && !name) name = k;
      else if (k->kind == Node::Fin && !next) next = k;
      else if (k->kind == Node::Name)
        p.fail(k->col, "two regions at once ('" + name->name + "' & '" + k->name + "') under one F",
               "each F holds one region and the rest of the mission, F(a & F(...))");
      else if (k->kind == Node::Fin)
        p.fail(k->col, "a second F under one F (unordered visits)",
               "each F holds one region and the rest of the mission, F(a & F(...))");
      else
        p.fail(k->col, "unsupported " + describe(*k) + " inside an F", "G and ! appear only at the top level, as G !obstacle");
    }
    if (!next) p.fail(name->col, "'" + name->name + "' without the rest of the mission", "write F(" + name->name + " & F(...)), the last F goal");
    if (name->name == "goal")
      p.fail(name->col, "'goal' before the end of the chain", "the goal is the last stage: F goal is the innermost F");
    visits.emplace_back(name->name, name->col);
    f = next;
  }
}

}  // namespace

void check_regions(const Field& regions) {
  if (!regions.present()) return;
  regions.expect_map();
  for (const auto& key : regions.keys()) {
    const Field r = regions.child(key);
    if (const std::string why = name_defect(key); !why.empty()) r.fail(why);
    for (const auto& w : kReserved)
      if (key == w) r.fail("'" + key + "' is a reserved word of the LTL form (F, G, goal, obstacles, ...); rename the region");
    r.expect_map();
  }
}

LtlMission read_ltl(const Field& f, const Field& regions, const AgentSpec& a, int horizon) {
  if (!f.is_scalar()) f.fail("expected a formula as a string, e.g. \"F(pickup & F goal) & G !obstacles\"");
  Parser p(f, f.text());
  const Node root = p.formula();
  std::vector<const Node*> terms;
  flatten(root, terms);

  LtlMission out;
  std::vector<std::pair<std::string, int>> visits;
  const Node* chain = nullptr;
  for (const Node* t : terms) {
    switch (t->kind) {
      case Node::Fin:
        if (chain)
          p.fail(t->col, "a second F chain (the first at column " + std::to_string(chain->col) + ")",
                 "a mission is one sequence: nest the visits, F(a & F(b & F goal))");
        chain = t;
        read_chain(p, *t, visits);
        break;
      case Node::Glob: {
        const Node& k = t->kids[0];
        if (k.kind != Node::Not || k.kids[0].kind != Node::Name)
          p.fail(k.col, "unsupported G over " + describe(k),
                 "G is supported only as G !name (an obstacle, or obstacles for all of them)");
        out.avoid.push_back({k.kids[0].name, k.kids[0].col});
        break;
      }
      case Node::Name:
        p.fail(t->col, "a bare name '" + t->name + "' at the top level (be there at the start)",
               "write F(" + t->name + " & F goal) to visit it");
      default:
        p.fail(t->col, "unsupported " + describe(*t) + " at the top level",
               "the formula is the chain F(a & F(... F goal)) and any number of G !obstacle, joined by &");
    }
  }
  if (!chain) p.fail(1, "missing 'F goal'", "the formula holds the chain F(a & F(... F goal)), or just F goal");

  std::vector<std::string> names = regions.keys();
  std::map<std::string, int> seen;
  for (const auto& [name, col] : visits) {
    if (auto [it, fresh] = seen.try_emplace(name, col); !fresh)
      p.fail(col, "region '" + name + "' visited a second time (first at column " + std::to_string(it->second) + ")",
             "stage names are unique per agent: give the second visit its own region name");
    const Field rf = regions.child(name);
    if (!rf.present()) {
      const std::string near = yaml::nearest(name, names);
      p.fail(col, "unknown region '" + name + "'" + (near.empty() ? "" : " (did you mean '" + near + "'?)"),
             names.empty() ? "the problem has no 'regions'" : "regions: " + join(names));
    }
    MissionStage st;
    st.name = name;
    try {
      read_stage_region(rf, a, st);
    } catch (const ConfigError& e) {
      // The region is shared; its defect may be this agent's (its eps, its workspace map).
      throw ConfigError(e.file(), e.line(), e.column(), e.path(),
                        e.message() + " (for agent '" + a.name + "', which visits it in " + f.path() + ")");
    }
    out.stages.push_back(std::move(st));
  }
  if (out.stages.size() > 1000) f.fail("expected at most 1000 stages, got " + std::to_string(out.stages.size()));
  check_mission_horizon(f, a, out.stages, horizon);
  return out;
}

void check_ltl_avoid(const Field& f, const std::vector<LtlAvoid>& avoid, const std::vector<Obstacle>& obstacles) {
  std::vector<std::string> names;
  for (const auto& o : obstacles) names.push_back(o.name);
  for (const auto& g : avoid) {
    if (g.name == "obstacles") continue;
    bool found = false, staged = false;
    for (const auto& o : obstacles)
      if (o.name == g.name) found = true, staged = o.staged;
    if (staged)
      f.fail("G !" + g.name + " at column " + std::to_string(g.column) + " of the formula \"" + f.text() +
             "\" names obstacle '" + g.name + "', which has 'scope: stages': the LTL form has no stages to bind it to; "
             "write this mission as 'stages' with 'avoid' or 'avoid_after'");
    if (found) continue;
    std::string msg = "G !" + g.name + " at column " + std::to_string(g.column) + " of the formula \"" + f.text() +
                      "\" names no obstacle";
    const std::string near = yaml::nearest(g.name, names);
    if (!near.empty()) msg += " (did you mean '" + near + "'?)";
    msg += names.empty() ? "; the problem has no obstacles" : "; obstacles: " + join(names);
    f.fail(msg + " (every agent avoids every obstacle; G !name only checks that the name exists)");
  }
}

}  // namespace marsyn::loader
