#include "device_daemons/voice/evaluation.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "common/stats/percentile.h"

namespace igms::voice {
namespace {

std::string VoiceLabel(const SpeechRequest& speech) {
  return speech.synthesizer == Synthesizer::kEspeakNg ? speech.voice : "flite:" + speech.voice;
}

}  // namespace

const std::vector<Voice>& TuningVoices() {
  // Two accents and two variants at two speeds were the first tuning set; the other eight
  // add two more accents, six more variants and six more speeds (none of the test set's).
  static const std::vector<Voice> voices = {{"en-us", 140},
                                            {"en-us", 190},
                                            {"en-gb+f3", 140},
                                            {"en-gb+f3", 190},
                                            {"en-gb-x-gbclan+m1", 170},
                                            {"en-gb-x-gbcwmd+f1", 130},
                                            {"en-us+m2", 220},
                                            {"en-gb+m5", 180},
                                            {"en-us+f5", 165},
                                            {"en-gb-x-gbcwmd+m7", 145},
                                            {"en-us+m6", 230},
                                            {"en-gb-x-gbclan+f3", 185}};
  return voices;
}

const std::vector<std::string>& TuningWords() {
  // Near misses of every command first, then short and unrelated words; none in TestWords().
  static const std::vector<std::string> words = {
      // freeze, unfreeze
      "breeze", "freezer", "free", "fleas", "sneeze", "freezing", "frozen", "reeds", "unease",
      "defrost",
      // range
      "rang", "ranger", "rage", "ranch", "grange", "wrench", "ray", "danger", "arranged",
      // mark, unmark
      "market", "marked", "remark", "mask", "bark", "march", "spark", "monk", "unmask", "embark",
      "mike",
      // remove points, remove model
      "remove", "points", "model", "remote", "removing", "appoints", "remodel", "movie", "joints",
      "bottle", "move it",
      // box
      "blocks", "boxes", "books", "bucks", "locks", "rocks", "bob", "ox",
      // cylinder
      "cinder", "cylinders", "splendor", "silly", "sender", "tinder", "linda",
      // wireframe, solid
      "wire", "frame", "fire", "famous", "wide frame", "solitude", "solo", "salt", "solely",
      "stolid", "squid", "sullen",
      // short and unrelated
      "hello", "table", "seven", "stop", "go", "yes", "no", "up", "down", "left", "right", "one",
      "two", "four", "six", "eight", "nine", "hi", "oops", "what", "why", "now", "wait", "help",
      "cancel", "undo", "next", "save", "open", "close", "print", "light", "sorry", "please",
      "excuse me", "hold on", "look here", "turn it around", "is that right", "very good"};
  return words;
}

const std::vector<Voice>& TestVoices() {
  static const std::vector<Voice> voices = {{"en-gb-scotland+m3", 160},
                                            {"en-029+f2", 210},
                                            {"en-us-nyc+m4", 150},
                                            {"en-gb-x-rp+f4", 200}};
  return voices;
}

const std::vector<Voice>& FliteTestVoices() {
  // flite's 16 kHz voices: a US female (slt), a Scottish male (awb), a US male (rms) and a
  // US male diphone voice (kal16), at speeds other than the enrolment's 175 wpm.
  static const std::vector<Voice> voices = {{"slt", 150, Synthesizer::kFlite},
                                            {"awb", 190, Synthesizer::kFlite},
                                            {"rms", 160, Synthesizer::kFlite},
                                            {"kal16", 210, Synthesizer::kFlite}};
  return voices;
}

const std::vector<std::string>& TestWords() {
  // 24 near misses (sound like a command) and 28 unrelated words and phrases. No homophone
  // of a command: "frees" (F R IY Z, as "freeze") was one until it was replaced by "pencil".
  static const std::vector<std::string> words = {
      "pencil",    "fries",      "freed",          "three",    "cheese",    "strange", "change",
      "arrange",   "rain",       "refreeze",       "park",     "dark",      "marker",  "marking",
      "unpack",    "fox",        "socks",          "calendar", "slender",   "salad",   "valid",
      "fireman",   "removal",    "pointer",        "modeling", "computer",  "camera",  "video",
      "joystick",  "banana",     "elephant",       "window",   "seventeen", "eleven",  "forty",
      "green",     "orange",     "water",          "coffee",   "morning",   "station", "robot",
      "system",    "again",      "okay",           "maybe",    "never",     "ready",   "finish",
      "thank you", "good night", "what time is it"};
  return words;
}

RecognizerOptions WithoutEvaluationWords(RecognizerOptions options) {
  for (const auto* list : {&TuningWords(), &TestWords()}) {
    for (const std::string& phrase : *list) {
      std::istringstream words(phrase);
      for (std::string word; words >> word;) options.fillers.excluded.push_back(word);
    }
  }
  return options;
}

std::vector<CorpusItem> BuildCorpus(const std::vector<Voice>& voices,
                                    const std::vector<std::string>& out_of_vocabulary,
                                    int oov_voices_per_word) {
  std::vector<CorpusItem> corpus;
  for (const Voice& voice : voices) {
    for (const CommandInfo& info : AllCommands()) {
      CorpusItem item;
      item.speech = voice.Say(std::string(info.phrase));
      item.expected = info.command;
      for (OperatorState s : AllStates()) {
        if (IsValid(s, info.command)) {
          item.state = s;
          break;
        }
      }
      corpus.push_back(item);
    }
  }
  if (voices.empty()) return corpus;
  size_t next_voice = 0;
  for (const std::string& word : out_of_vocabulary) {
    for (int i = 0; i < oov_voices_per_word; ++i) {
      const Voice& voice = voices[next_voice++ % voices.size()];
      CorpusItem item;
      item.speech = voice.Say(word);
      corpus.push_back(item);
    }
  }
  return corpus;
}

void EvaluationReport::Append(const EvaluationReport& other) {
  commands += other.commands;
  recognised += other.recognised;
  out_of_vocabulary += other.out_of_vocabulary;
  false_accepts += other.false_accepts;
  decode_ms.insert(decode_ms.end(), other.decode_ms.begin(), other.decode_ms.end());
  results.insert(results.end(), other.results.begin(), other.results.end());
}

double EvaluationReport::decode_ms_quantile(double q) const {
  return decode_ms.empty() ? 0.0 : stats::Percentile(decode_ms, q);
}

std::string EvaluationReport::Summary() const {
  std::ostringstream out;
  out.precision(1);
  out << std::fixed;
  out << "recognised " << recognised << "/" << commands << " commands ("
      << 100.0 * recognition_rate() << "%, target >= 95%)\n";
  out << "false accepts " << false_accepts << "/" << out_of_vocabulary
      << " out-of-vocabulary utterances (" << 100.0 * false_accept_rate() << "%, target <= 5%)\n";
  out << "decode time per utterance: median " << decode_ms_quantile(0.5) << " ms, p90 "
      << decode_ms_quantile(0.9) << " ms, max " << decode_ms_quantile(1.0) << " ms over "
      << decode_ms.size() << " utterances\n";
  return out.str();
}

std::string EvaluationReport::Failures() const { return Lines(false); }
std::string EvaluationReport::All() const { return Lines(true); }

std::string EvaluationReport::Lines(bool all) const {
  std::ostringstream out;
  out.precision(2);
  out << std::fixed;
  for (const ItemResult& r : results) {
    if (r.correct && !all) continue;
    out << (r.correct ? "  ok " : "  WRONG ");
    out << "  \"" << r.item.speech.text << "\" " << VoiceLabel(r.item.speech) << " "
        << r.item.speech.words_per_minute << " wpm in " << StateName(r.item.state) << ": "
        << (r.recognition.accepted
                ? "accepted as \"" + std::string(Phrase(*r.recognition.command)) + "\""
                : "rejected, " + std::string(RejectReasonName(r.recognition.reason)))
        << " (heard \"" << r.recognition.hypothesis << "\", confidence " << r.recognition.confidence
        << ", score " << r.recognition.score_per_frame << ", uncovered "
        << r.recognition.uncovered_speech_ms << " ms, agreement " << r.recognition.agreement
        << (r.recognition.verification.empty()
                ? std::string()
                : ", verified as \"" + r.recognition.verification + "\"")
        << ")\n";
  }
  return out.str();
}

std::string EvaluationReport::Csv() const {
  std::ostringstream out;
  out << "text,voice,wpm,state,expected,hypothesis,accepted,reason,confidence,score_per_frame,"
         "uncovered_ms,command_ms,agreement,audio_s,decode_ms\n";
  for (const ItemResult& r : results) {
    const Recognition& g = r.recognition;
    out << r.item.speech.text << "," << VoiceLabel(r.item.speech) << ","
        << r.item.speech.words_per_minute << "," << StateName(r.item.state) << ","
        << (r.item.expected ? CommandToken(*r.item.expected) : std::string()) << "," << g.hypothesis
        << "," << g.accepted << "," << RejectReasonName(g.reason) << "," << g.confidence << ","
        << g.score_per_frame << "," << g.uncovered_speech_ms << "," << g.command_ms << ","
        << g.agreement << "," << g.audio_seconds << "," << g.decode_ms << "\n";
  }
  return out.str();
}

std::string EvaluationReport::Sweep(const std::vector<double>& thresholds) const {
  std::ostringstream out;
  out.precision(1);
  out << std::fixed;
  for (double t : thresholds) {
    int recognised_at = 0, false_at = 0;
    for (const ItemResult& r : results) {
      const Recognition& g = r.recognition;
      const bool accepted = (g.accepted || g.reason == RejectReason::kLowConfidence) && g.command &&
                            IsValid(r.item.state, *g.command) && g.confidence >= t;
      if (r.item.expected) {
        recognised_at += accepted && g.command == r.item.expected;
      } else {
        false_at += accepted;
      }
    }
    out << "  min_confidence " << std::setprecision(2) << t << std::setprecision(1)
        << ": recognised " << (commands ? 100.0 * recognised_at / commands : 0.0)
        << "%, false accepts " << (out_of_vocabulary ? 100.0 * false_at / out_of_vocabulary : 0.0)
        << "%\n";
  }
  return out.str();
}

Result<EvaluationReport> Evaluate(Recognizer& recognizer, const std::vector<CorpusItem>& corpus) {
  EvaluationReport report;
  for (const CorpusItem& item : corpus) {
    Result<Audio> audio = Synthesize(item.speech);
    if (!audio.ok()) return ErrorMessage{audio.error()};
    recognizer.SetState(item.state);
    ItemResult result{item, recognizer.Recognize(audio->samples), false};
    report.decode_ms.push_back(result.recognition.decode_ms);
    if (item.expected) {
      ++report.commands;
      result.correct = result.recognition.accepted && result.recognition.command == item.expected;
      report.recognised += result.correct;
    } else {
      ++report.out_of_vocabulary;
      result.correct = !result.recognition.accepted;
      report.false_accepts += !result.correct;
    }
    report.results.push_back(std::move(result));
  }
  return report;
}

Result<std::vector<AdaptationUtterance>> SynthesizeEnrolment(
    const std::vector<Voice>& voices, const std::vector<std::string>& prompts) {
  std::vector<AdaptationUtterance> out;
  for (const Voice& voice : voices) {
    for (const std::string& prompt : prompts) {
      auto audio = Synthesize(voice.Say(prompt));
      if (!audio.ok()) return ErrorMessage{audio.error()};
      out.push_back({std::move(*audio), prompt});
    }
  }
  return out;
}

Result<EvaluationReport> EvaluateEnrolled(const std::vector<Voice>& voices,
                                          const std::vector<std::string>& out_of_vocabulary,
                                          int enrolment_wpm, const RecognizerOptions& options,
                                          const std::string& work_dir) {
  EvaluationReport all;
  for (const Voice& voice : voices) {
    Voice enrolling = voice;
    enrolling.words_per_minute = enrolment_wpm;
    auto enrolment = SynthesizeEnrolment({enrolling});
    if (!enrolment.ok()) return ErrorMessage{enrolment.error()};
    AdaptationOptions adaptation;
    adaptation.model_dir = options.model_dir;
    adaptation.out_dir = (std::filesystem::path(work_dir) / ("enrolled-" + voice.name)).string();
    const AdaptationReport adapted = AdaptModel(*enrolment, adaptation);
    if (!adapted.ok()) return ErrorMessage{"adapting to " + voice.name + ": " + adapted.error};
    RecognizerOptions enrolled = options;
    enrolled.model_dir = adaptation.out_dir;
    std::string error;
    auto recognizer = Recognizer::Create(enrolled, &error);
    Result<EvaluationReport> report = ErrorMessage{error};
    if (recognizer) report = Evaluate(*recognizer, BuildCorpus({voice}, out_of_vocabulary, 1));
    std::filesystem::remove_all(adaptation.out_dir);
    if (!report.ok()) return report;
    all.Append(*report);
  }
  return all;
}

}  // namespace igms::voice
