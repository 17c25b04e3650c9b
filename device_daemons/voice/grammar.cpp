#include "device_daemons/voice/grammar.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace igms::voice {
namespace {

// How many phones a dictionary word may differ from `command` by and still be its decoy.
int DecoyDistanceLimit(const DecoyOptions& options, const Pronunciation& command) {
  return std::max(1, static_cast<int>(std::lround(options.max_distance_fraction *
                                                  static_cast<double>(command.phones.size()))));
}

int SizeGap(const Pronunciation& a, const Pronunciation& b) {
  return std::abs(static_cast<int>(a.phones.size()) - static_cast<int>(b.phones.size()));
}

std::vector<std::string> Split(std::string_view text) {
  std::istringstream in{std::string(text)};
  std::vector<std::string> out;
  for (std::string item; in >> item;) out.push_back(item);
  return out;
}

// The phones are written out here rather than looked up so that a grammar never depends
// on which dictionary happens to be installed.
std::vector<std::string> CommandPhones(Command command) {
  switch (command) {
    case Command::kFreeze:
      return Split("F R IY Z");
    case Command::kRange:
      return Split("R EY N JH");
    case Command::kUnfreeze:
      return Split("AH N F R IY Z");
    case Command::kMark:
      return Split("M AA R K");
    case Command::kUnmark:
      return Split("AH N M AA R K");
    case Command::kRemovePoints:
      return Split("R IY M UW V P OY N T S");
    case Command::kBox:
      return Split("B AA K S");
    case Command::kCylinder:
      return Split("S IH L AH N D ER");
    case Command::kWireframe:
      return Split("W AY ER F R EY M");
    case Command::kSolid:
      return Split("S AA L AH D");
    case Command::kRemoveModel:
      return Split("R IY M UW V M AA D AH L");
  }
  return {};
}

std::string FormatWeight(double weight) {
  // sphinxbase's JSGF lexer reads plain decimals only, not exponents.
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(40);
  out << weight;
  return out.str();
}

}  // namespace

std::string CommandToken(Command command) {
  std::string token(Phrase(command));
  std::replace(token.begin(), token.end(), ' ', '_');
  return token;
}

std::optional<Command> CommandFromToken(std::string_view token) {
  for (const CommandInfo& info : AllCommands()) {
    if (CommandToken(info.command) == token) return info.command;
  }
  return std::nullopt;
}

std::vector<Pronunciation> CommandPronunciations() {
  std::vector<Pronunciation> out;
  for (const CommandInfo& info : AllCommands()) {
    out.push_back({CommandToken(info.command), CommandPhones(info.command)});
  }
  return out;
}

std::vector<Pronunciation> AlternativePronunciations() {
  return {{CommandToken(Command::kRemovePoints) + "(2)", Split("R IH M UW V P OY N T S")},
          {CommandToken(Command::kRemoveModel) + "(2)", Split("R IH M UW V M AA D AH L")},
          {CommandToken(Command::kWireframe) + "(2)", Split("W AY R F R EY M")},
          {CommandToken(Command::kSolid) + "(2)", Split("S AA L IH D")},
          {CommandToken(Command::kCylinder) + "(3)", Split("S IH L IH N D AH")}};
}

const std::vector<std::string>& ModelPhones() {
  static const std::vector<std::string> phones = Split(
      "AA AE AH AO AW AY B CH D DH EH ER EY F G HH IH IY JH K L M N NG OW OY P R S SH T TH "
      "UH UW V W Y Z ZH");
  return phones;
}

std::string PhoneToken(std::string_view phone) {
  std::string token = "ph_";
  for (char c : phone)
    token.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  return token;
}

bool IsPhoneToken(std::string_view token) { return token.starts_with("ph_"); }

Result<std::vector<Pronunciation>> LoadDictionary(const std::string& path) {
  std::ifstream in(path);
  if (!in) return ErrorMessage{"cannot read the pronouncing dictionary " + path};
  std::vector<Pronunciation> out;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> fields = Split(line);
    if (fields.size() < 2) continue;
    const std::string& word = fields[0];
    if (!std::all_of(word.begin(), word.end(), [](char c) { return c >= 'a' && c <= 'z'; })) {
      continue;
    }
    Pronunciation entry{word, {}};
    for (size_t i = 1; i < fields.size(); ++i) {
      std::string phone = fields[i];
      while (!phone.empty() && std::isdigit(static_cast<unsigned char>(phone.back()))) {
        phone.pop_back();
      }
      entry.phones.push_back(phone);
    }
    out.push_back(std::move(entry));
  }
  if (out.empty()) {
    return ErrorMessage{"the pronouncing dictionary " + path + " holds no usable entry"};
  }
  return out;
}

int PhoneDistance(const std::vector<std::string>& a, const std::vector<std::string>& b) {
  std::vector<int> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = static_cast<int>(j);
  for (size_t i = 1; i <= a.size(); ++i) {
    int diagonal = row[0];
    row[0] = static_cast<int>(i);
    for (size_t j = 1; j <= b.size(); ++j) {
      const int above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

bool DecoyOptions::Check(std::string* error) const {
  if (!(max_distance_fraction >= 0.0 && max_distance_fraction <= 1.0)) {
    if (error) *error = "decoy max_distance_fraction must be in [0, 1]";
    return false;
  }
  if (max_per_command < 0 || min_phones < 1) {
    if (error) *error = "decoy max_per_command must be >= 0 and min_phones >= 1";
    return false;
  }
  return true;
}

std::vector<Pronunciation> SelectDecoys(const std::vector<Pronunciation>& dictionary,
                                        const DecoyOptions& options,
                                        const UnigramFn& log10_unigram) {
  const std::vector<Pronunciation> commands = CommandPronunciations();
  std::set<std::vector<std::string>> command_phones;
  for (const Pronunciation& c : commands) command_phones.insert(c.phones);

  std::map<std::string, Pronunciation> chosen;
  for (const Pronunciation& command : commands) {
    const int limit = DecoyDistanceLimit(options, command);
    std::vector<std::pair<int, const Pronunciation*>> near;
    for (const Pronunciation& entry : dictionary) {
      if (static_cast<int>(entry.phones.size()) < options.min_phones) continue;
      if (command_phones.count(entry.phones)) continue;  // homophones are the command
      if (SizeGap(entry, command) > limit) continue;
      const int d = PhoneDistance(entry.phones, command.phones);
      if (d < 1 || d > limit) continue;
      if (log10_unigram && log10_unigram(entry.word) < options.min_log10_unigram) continue;
      near.push_back({d, &entry});
    }
    std::sort(near.begin(), near.end(), [](const auto& x, const auto& y) {
      return x.first != y.first ? x.first < y.first : x.second->word < y.second->word;
    });
    const size_t keep = std::min(near.size(), static_cast<size_t>(options.max_per_command));
    for (size_t i = 0; i < keep; ++i) chosen.emplace(near[i].second->word, *near[i].second);
  }
  for (const Pronunciation& c : commands) chosen.erase(c.word);
  std::vector<Pronunciation> out;
  out.reserve(chosen.size());
  for (auto& [word, entry] : chosen) out.push_back(entry);
  return out;
}

bool FillerWordOptions::Check(std::string* error) const {
  if (count < 0 || margin < 0 || min_phones < 1 || !(weight > 0.0 && std::isfinite(weight))) {
    if (error) *error = "filler words: count and margin must be >= 0, min_phones >= 1, weight > 0";
    return false;
  }
  return true;
}

std::vector<Pronunciation> SelectFillerWords(const std::vector<Pronunciation>& dictionary,
                                             const FillerWordOptions& options,
                                             const DecoyOptions& decoys,
                                             const UnigramFn& log10_unigram) {
  if (options.count == 0 || !log10_unigram) return {};
  const std::vector<Pronunciation> commands = CommandPronunciations();
  const std::set<std::string> excluded(options.excluded.begin(), options.excluded.end());
  std::vector<std::pair<double, const Pronunciation*>> ranked;
  for (const Pronunciation& entry : dictionary) {
    if (static_cast<int>(entry.phones.size()) < options.min_phones) continue;
    if (excluded.count(entry.word)) continue;
    const double u = log10_unigram(entry.word);
    if (u < -20.0) continue;  // not in the language model
    ranked.push_back({u, &entry});
  }
  std::sort(ranked.begin(), ranked.end(), [](const auto& x, const auto& y) {
    return x.first != y.first ? x.first > y.first : x.second->word < y.second->word;
  });
  std::vector<Pronunciation> out;
  for (const auto& ranked_entry : ranked) {
    const Pronunciation* entry =
        ranked_entry.second;  // a lambda cannot capture a binding in clang 14
    if (static_cast<int>(out.size()) >= options.count) break;
    const bool near = std::any_of(commands.begin(), commands.end(), [&](const Pronunciation& c) {
      const int limit = DecoyDistanceLimit(decoys, c) + options.margin;
      return c.word == entry->word ||
             (SizeGap(*entry, c) <= limit && PhoneDistance(entry->phones, c.phones) <= limit);
    });
    if (!near) out.push_back(*entry);
  }
  return out;
}

bool GrammarOptions::Check(std::string* error) const {
  for (double w : {other_state_weight, decoy_weight}) {
    if (!(w > 0.0 && std::isfinite(w))) {
      if (error) *error = "grammar weights must be positive and finite";
      return false;
    }
  }
  if (!(phone_loop_weight >= 0.0 && std::isfinite(phone_loop_weight)) || max_phones < 1) {
    if (error) *error = "phone_loop_weight must be >= 0 and max_phones >= 1";
    return false;
  }
  return true;
}

std::string BuildVerificationGrammar(const std::vector<Pronunciation>& fillers,
                                     double filler_weight) {
  std::string utterance;
  for (const CommandInfo& info : AllCommands())
    utterance += (utterance.empty() ? "" : " | ") + CommandToken(info.command);
  for (const Pronunciation& f : fillers)
    utterance += " | /" + FormatWeight(filler_weight) + "/ " + f.word;
  return "#JSGF V1.0;\n\ngrammar igms_verify;\n\npublic <utterance> = " + utterance + ";\n";
}

std::string BuildGrammar(OperatorState state, const std::vector<Pronunciation>& decoys,
                         const GrammarOptions& options) {
  std::vector<std::string> valid, other;
  for (const CommandInfo& info : AllCommands()) {
    (IsValid(state, info.command) ? valid : other).push_back(CommandToken(info.command));
  }
  auto alternatives = [](const std::vector<std::string>& tokens) {
    std::string out;
    for (const std::string& t : tokens) out += (out.empty() ? "" : " | ") + t;
    return out;
  };
  const auto& model_phones = ModelPhones();
  std::vector<std::string> phones;
  phones.reserve(model_phones.size());
  for (const std::string& p : model_phones) phones.push_back(PhoneToken(p));
  std::vector<std::string> decoy_words;
  decoy_words.reserve(decoys.size());
  for (const Pronunciation& d : decoys) decoy_words.push_back(d.word);

  // Every weighted alternative is written as a word in the public rule, not as a reference
  // to a rule of its own: sphinxbase ignores the weight of a rule reference (measured: the
  // same hypotheses from weights 1 to 1e-25), and applies the weight of a word.
  std::ostringstream g;
  g << "#JSGF V1.0;\n\ngrammar igms_" << StateName(state) << ";\n\n";
  g << "<command> = " << alternatives(valid) << ";\n";
  std::string utterance = "<command>";
  for (const std::string& t : other)
    utterance += " | /" + FormatWeight(options.other_state_weight) + "/ " + t;
  for (const std::string& d : decoy_words)
    utterance += " | /" + FormatWeight(options.decoy_weight) + "/ " + d;
  if (options.phone_loop_weight > 0.0) {
    // Bounded, not "<phone>+": sphinxbase's JSGF compiler closes a loop over the whole
    // alternation, which lets phones and commands mix in one path. Each first phone is its
    // own weighted alternative, so the weight is applied (above).
    g << "<phone> = " << alternatives(phones) << ";\n";
    std::string nested = "<phone>";
    for (int i = 2; i < options.max_phones; ++i) nested.insert(0, "<phone> [").append("]");
    if (options.max_phones > 1) g << "<tail> = " << nested << ";\n";
    for (const std::string& p : phones) {
      utterance += " | /" + FormatWeight(options.phone_loop_weight) + "/ " + p +
                   (options.max_phones > 1 ? " [<tail>]" : "");
    }
  }
  g << "\npublic <utterance> = " << utterance << ";\n";
  return g.str();
}

}  // namespace igms::voice
