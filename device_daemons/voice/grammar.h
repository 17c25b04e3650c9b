// JSGF grammars, one per operator state, and the dictionary words they need.
//
// A grammar that holds only the command words maps any speech at all onto the nearest
// command, so each state's grammar also lists what the operator might say instead, to
// catch it and reject it (Cooke, section 2.1.6: "the more words available the more likely
// random speech will be interpreted as a vocal command"):
//   - the state's valid commands (the only accepted results),
//   - the other states' commands (recognised so they can be rejected as "not valid now"
//     rather than heard as a similar valid word: "unfreeze" while in verification),
//   - decoys: dictionary words whose pronunciation is within a small phone edit distance of
//     some command ("breeze", "marked", "rang"), chosen from the pronouncing dictionary by
//     distance alone, homophones of a command excluded,
//   - a loop of single phones, the catch-all for any other speech.
// Decoys and the phone loop are off by default. Weighted far below the commands (1e-15),
// decoys trade genuine commands for false accepts: on the tuning set that trade looked
// better than the confidence threshold's, on the test set it did not (docs/voice.md). The
// phone loop cost more commands than decoys for the same false accepts.
//
// Every command is one dictionary token, the phrase with '_' for spaces ("remove_points"),
// so a two-word command has one posterior. Phones are the 39 of the CMU dictionary (the
// en-us acoustic model's set); phone-loop tokens are "ph_" plus the lower-case phone.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/base/result.h"
#include "device_daemons/voice/command_language.h"

namespace igms::voice {

struct Pronunciation {
  std::string word;                 // lower case, [a-z_] only
  std::vector<std::string> phones;  // upper case CMU phones without stress digits
};

// The grammar token of a command ("remove_points") and the command of a token.
std::string CommandToken(Command command);
std::optional<Command> CommandFromToken(std::string_view token);
// The pronunciation of every command's token (in code order). The CMU dictionary lacks
// "unfreeze", "unmark" and "wireframe"; their entries are built from "freeze", "mark",
// "wire" and "frame".
std::vector<Pronunciation> CommandPronunciations();
// More pronunciations, added as "token(2)" after the first: "remove" with IH as the British
// voices say it (both two-word commands), "wire" in one syllable, "solid" with IH in its
// second syllable, and, as "cylinder(3)" since the CMU dictionary's own "cylinder(2)" comes
// with it already, a cylinder without the final R (S IH L IH N D AH), as non-rhotic
// accents say it.
std::vector<Pronunciation> AlternativePronunciations();
// The 39 phones of the model and the phone-loop tokens made from them.
const std::vector<std::string>& ModelPhones();
std::string PhoneToken(std::string_view phone);
bool IsPhoneToken(std::string_view token);

// Reads a CMU-format pronouncing dictionary ("word  PH1 PH2 ...", alternates written
// "word(2)" are skipped, words with characters other than a-z are skipped). An error when
// the file cannot be read or holds no entry.
Result<std::vector<Pronunciation>> LoadDictionary(const std::string& path);

// Levenshtein distance between two phone sequences (insertions, deletions and
// substitutions all cost 1).
int PhoneDistance(const std::vector<std::string>& a, const std::vector<std::string>& b);

struct DecoyOptions {
  // A dictionary word is a decoy when its distance to some command is at least 1 and at
  // most this, scaled by the command's length: max(1, round(fraction * phones)).
  double max_distance_fraction = 0.34;
  // At most this many decoys per command, nearest first (ties by word, for repeatability).
  // 0: no decoys. With decoys, 15 (with min_confidence 0.1) was the tuning set's choice
  // (docs/voice.md); the limits below leave fewer than that for most commands.
  int max_per_command = 0;
  // Words shorter than this many phones are never decoys (they match fragments of speech).
  int min_phones = 2;
  // Only words at least this common are decoys: log10 of the word's unigram probability in
  // an English language model. Rare words (names, spellings of foreign words) would only
  // steal genuine commands said with an odd accent.
  double min_log10_unigram = -5.0;
  bool Check(std::string* error) const;
};

// Decoys for the whole command language, sorted by word, without duplicates and without
// any word whose pronunciation equals a command's.
// `log10_unigram` gives a word's log10 unigram probability (-inf or very low when unknown);
// without it every word counts as common.
using UnigramFn = std::function<double(const std::string& word)>;
std::vector<Pronunciation> SelectDecoys(const std::vector<Pronunciation>& dictionary,
                                        const DecoyOptions& options,
                                        const UnigramFn& log10_unigram = {});

// Common English words that are no command: what an operator talking to someone else says.
// A command the state's grammar accepted is decoded once more against every command and
// these words; "banana" heard as "unmark" is then heard as some word nearer to it. They are
// not in the state grammars: pocketsphinx applies a word's weight at its last phone, so
// thousands of cheap prefixes crowd the commands out of its narrow beams. Off by default.
struct FillerWordOptions {
  // The this-many most common dictionary words (by unigram) farther from every command than
  // a decoy may be (DecoyOptions::max_distance_fraction) plus `margin` phones.
  int count = 0;
  int margin = 0;
  int min_phones = 2;
  // Each filler's weight relative to a command's.
  double weight = 1.0;
  // Never fillers: an evaluation leaves its own out-of-vocabulary words out, so it measures
  // words the grammar has not been given.
  std::vector<std::string> excluded;
  bool Check(std::string* error) const;
};

// Filler words, most common first. Empty without `log10_unigram`.
std::vector<Pronunciation> SelectFillerWords(const std::vector<Pronunciation>& dictionary,
                                             const FillerWordOptions& options,
                                             const DecoyOptions& decoys,
                                             const UnigramFn& log10_unigram);

struct GrammarOptions {
  // JSGF weights of the alternatives relative to a command (1.0). Each alternative is
  // written as a weighted word: sphinxbase ignores the weight of a rule reference.
  double other_state_weight = 1.0;
  // Chosen on the tuning set, with 15 decoys per command and min_confidence 0.1.
  double decoy_weight = 1e-15;
  // 0 leaves the phone loop out.
  double phone_loop_weight = 0.0;
  int max_phones = 10;
  bool Check(std::string* error) const;
};

// The JSGF text of a state's grammar, named "igms_<state name>", whose public rule is
// <utterance>. Decoys may be empty.
std::string BuildGrammar(OperatorState state, const std::vector<Pronunciation>& decoys,
                         const GrammarOptions& options);

// The JSGF text of the verification grammar "igms_verify": every command, or one filler word
// at `filler_weight`.
std::string BuildVerificationGrammar(const std::vector<Pronunciation>& fillers,
                                     double filler_weight);

}  // namespace igms::voice
