#include "device_daemons/voice/grammar.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

namespace igms::voice {
namespace {

std::vector<std::string> P(const std::string& s) {
  std::vector<std::string> out;
  size_t i = 0;
  while (i < s.size()) {
    const size_t j = s.find(' ', i);
    out.push_back(s.substr(i, j == std::string::npos ? std::string::npos : j - i));
    if (j == std::string::npos) break;
    i = j + 1;
  }
  return out;
}

TEST(Grammar, TokensRoundTrip) {
  EXPECT_EQ(CommandToken(Command::kRemovePoints), "remove_points");
  for (const CommandInfo& info : AllCommands()) {
    EXPECT_EQ(CommandFromToken(CommandToken(info.command)), info.command);
  }
  EXPECT_FALSE(CommandFromToken("remove"));
}

TEST(Grammar, PronunciationsCoverTheMissingWords) {
  const auto words = CommandPronunciations();
  ASSERT_EQ(words.size(), AllCommands().size());
  for (const Pronunciation& p : words) {
    EXPECT_FALSE(p.phones.empty()) << p.word;
    for (const std::string& phone : p.phones) {
      EXPECT_NE(std::find(ModelPhones().begin(), ModelPhones().end(), phone), ModelPhones().end())
          << phone << " in " << p.word;
    }
  }
  EXPECT_EQ(words[2].word, "unfreeze");
  EXPECT_EQ(words[2].phones, P("AH N F R IY Z"));
}

TEST(Grammar, AlternativePronunciationsNameACommand) {
  for (const Pronunciation& p : AlternativePronunciations()) {
    // "token(N)", N from 2 (3 where the CMU dictionary has a "(2)" of its own).
    ASSERT_TRUE(p.word.size() > 3 && p.word.ends_with(")") && p.word[p.word.size() - 3] == '(')
        << p.word;
    EXPECT_GE(p.word[p.word.size() - 2], '2') << p.word;
    EXPECT_TRUE(CommandFromToken(p.word.substr(0, p.word.size() - 3))) << p.word;
    for (const std::string& phone : p.phones) {
      EXPECT_NE(std::find(ModelPhones().begin(), ModelPhones().end(), phone), ModelPhones().end())
          << phone << " in " << p.word;
    }
  }
}

TEST(Grammar, PhoneDistance) {
  EXPECT_EQ(PhoneDistance(P("F R IY Z"), P("F R IY Z")), 0);
  EXPECT_EQ(PhoneDistance(P("F R IY Z"), P("B R IY Z")), 1);       // breeze
  EXPECT_EQ(PhoneDistance(P("F R IY Z"), P("AH N F R IY Z")), 2);  // unfreeze
  EXPECT_EQ(PhoneDistance({}, P("B AA K S")), 4);
}

TEST(Grammar, EachStateListsItsCommandsFirstAndTheOthersApart) {
  for (OperatorState state : AllStates()) {
    const std::string g = BuildGrammar(state, {}, {});
    EXPECT_NE(g.find("#JSGF V1.0;"), std::string::npos);
    EXPECT_NE(g.find("grammar igms_" + std::string(StateName(state)) + ";"), std::string::npos);
    const size_t command_line = g.find("<command> =");
    const std::string commands = g.substr(command_line, g.find('\n', command_line) - command_line);
    for (const CommandInfo& info : AllCommands()) {
      const bool listed = commands.find(" " + CommandToken(info.command)) != std::string::npos;
      EXPECT_EQ(listed, IsValid(state, info.command)) << StateName(state) << " " << info.phrase;
      EXPECT_NE(g.find(CommandToken(info.command)), std::string::npos);
    }
    EXPECT_EQ(g.find("<phone>"), std::string::npos);  // phone loop off by default
  }
}

TEST(Grammar, OptionalPhoneLoopIsBoundedAndDecoysAppear) {
  GrammarOptions options;
  options.phone_loop_weight = 0.5;
  options.max_phones = 3;
  const std::string g =
      BuildGrammar(OperatorState::kVerification, {{"breeze", P("B R IY Z")}}, options);
  EXPECT_NE(g.find("/ breeze"), std::string::npos);
  EXPECT_NE(g.find("<tail> = <phone> [<phone>];"), std::string::npos);
  EXPECT_NE(g.find("/ ph_aa [<tail>]"), std::string::npos);
  EXPECT_EQ(g.find('+'), std::string::npos);
}

// sphinxbase applies a JSGF weight written before a word and ignores one written before a
// rule reference, so every weighted alternative must be a word of the public rule.
TEST(Grammar, WeightsAreWrittenOnWordsNotRuleReferences) {
  GrammarOptions options;
  options.other_state_weight = 0.5;
  options.decoy_weight = 0.25;
  options.phone_loop_weight = 0.125;
  const std::string g =
      BuildGrammar(OperatorState::kVerification, {{"breeze", P("B R IY Z")}}, options);
  const std::string rule = g.substr(g.find("public <utterance> ="));
  EXPECT_NE(rule.find("/0.50"), std::string::npos);
  EXPECT_NE(rule.find("0/ unfreeze"), std::string::npos);  // another state's command
  EXPECT_NE(rule.find("/0.250"), std::string::npos);
  EXPECT_NE(rule.find("0/ breeze"), std::string::npos);
  EXPECT_NE(rule.find("/0.1250"), std::string::npos);
  EXPECT_NE(rule.find("0/ ph_z [<tail>]"), std::string::npos);
  // The only rule reference at the top level is the state's own commands, unweighted.
  EXPECT_EQ(rule.find("/ <"), std::string::npos);
  EXPECT_EQ(rule.find("<other_state>"), std::string::npos);
  EXPECT_EQ(rule.find("<decoy>"), std::string::npos);
}

TEST(Grammar, DecoysAreNearButNeverHomophones) {
  const std::vector<Pronunciation> dictionary = {
      {"breeze", P("B R IY Z")},   {"frieze", P("F R IY Z")},           {"freeze", P("F R IY Z")},
      {"marked", P("M AA R K T")}, {"elephant", P("EH L AH F AH N T")}, {"o", P("OW")},
  };
  DecoyOptions options;
  options.max_per_command = 10;
  const auto decoys = SelectDecoys(dictionary, options);
  std::vector<std::string> words;
  words.reserve(decoys.size());
  for (const auto& d : decoys) words.push_back(d.word);
  EXPECT_EQ(words, (std::vector<std::string>{"breeze", "marked"}));
  // A word-frequency filter drops rare words.
  const auto common = SelectDecoys(
      dictionary, options, [](const std::string& w) { return w == "marked" ? -3.0 : -7.0; });
  ASSERT_EQ(common.size(), 1u);
  EXPECT_EQ(common[0].word, "marked");
  EXPECT_TRUE(SelectDecoys(dictionary, DecoyOptions{}).empty());  // off by default
}

TEST(Grammar, FillerWordsAreCommonWordsFarFromEveryCommand) {
  const std::vector<Pronunciation> dictionary = {
      {"the", P("DH AH")},
      {"o", P("OW")},
      {"breeze", P("B R IY Z")},
      {"freeze", P("F R IY Z")},
      {"banana", P("B AH N AE N AH")},
      {"water", P("W AO T ER")},
      {"morning", P("M AO R N IH NG")},
      {"zyzzyva", P("Z IH Z IH V AH")},
  };
  const std::map<std::string, double> unigram = {
      {"the", -1.0},    {"o", -2.0},     {"breeze", -4.0},  {"freeze", -4.0},
      {"banana", -4.5}, {"water", -3.0}, {"morning", -3.5},
  };
  auto log10_unigram = [&](const std::string& w) {
    const auto it = unigram.find(w);
    return it == unigram.end() ? -99.0 : it->second;
  };
  FillerWordOptions options;
  auto words = [&](const FillerWordOptions& o) {
    std::vector<std::string> out;
    for (const auto& f : SelectFillerWords(dictionary, o, DecoyOptions{}, log10_unigram))
      out.push_back(f.word);
    return out;
  };
  EXPECT_TRUE(words(options).empty());  // off by default
  options.count = 10;
  // Most common first; never a command, a decoy-near word ("breeze"), a one-phone word, or a
  // word the language model does not know.
  EXPECT_EQ(words(options), (std::vector<std::string>{"the", "water", "morning", "banana"}));
  options.count = 2;
  EXPECT_EQ(words(options), (std::vector<std::string>{"the", "water"}));
  options.count = 10;
  options.excluded = {"water", "the"};
  EXPECT_EQ(words(options), (std::vector<std::string>{"morning", "banana"}));
  EXPECT_TRUE(SelectFillerWords(dictionary, options, DecoyOptions{}, {}).empty());

  const std::string g = BuildVerificationGrammar(
      SelectFillerWords(dictionary, options, DecoyOptions{}, log10_unigram), 0.01);
  EXPECT_NE(g.find("grammar igms_verify;"), std::string::npos);
  for (const CommandInfo& info : AllCommands())
    EXPECT_NE(g.find(" " + CommandToken(info.command)), std::string::npos) << g;
  EXPECT_NE(g.find("/0.0100"), std::string::npos) << g;
  EXPECT_NE(g.find("/ banana;"), std::string::npos) << g;
}

TEST(Grammar, LoadDictionaryReportsProblems) {
  const auto missing = LoadDictionary("/nonexistent/dictionary.dict");
  EXPECT_FALSE(missing.ok());
  EXPECT_NE(missing.error().find("cannot read"), std::string::npos);
  const auto path = std::filesystem::temp_directory_path() / "igms_voice_test.dict";
  {
    std::ofstream out(path);
    out << "freeze F R IY1 Z\nfreeze(2) F R IY Z\no'brien OW B R AY AH N\nbox B AA1 K S\n";
  }
  const auto words = LoadDictionary(path.string());
  ASSERT_TRUE(words.ok()) << words.error();
  ASSERT_EQ(words->size(), 2u);
  EXPECT_EQ((*words)[0].phones, P("F R IY Z"));
  {
    std::ofstream out(path);
    out << "# nothing here\n";
  }
  const auto empty = LoadDictionary(path.string());
  EXPECT_FALSE(empty.ok());
  EXPECT_NE(empty.error().find("no usable entry"), std::string::npos);
  std::filesystem::remove(path);
}

TEST(Grammar, OptionChecks) {
  std::string error;
  EXPECT_TRUE(GrammarOptions{}.Check(&error));
  GrammarOptions bad;
  bad.decoy_weight = 0.0;
  EXPECT_FALSE(bad.Check(&error));
  DecoyOptions bad_decoys;
  bad_decoys.max_distance_fraction = 2.0;
  EXPECT_FALSE(bad_decoys.Check(&error));
  EXPECT_TRUE(FillerWordOptions{}.Check(&error));
  FillerWordOptions bad_fillers;
  bad_fillers.count = -1;
  EXPECT_FALSE(bad_fillers.Check(&error));
  bad_fillers.count = 10;
  bad_fillers.weight = std::nan("");
  EXPECT_FALSE(bad_fillers.Check(&error));
}

}  // namespace
}  // namespace igms::voice
