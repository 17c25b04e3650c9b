#include "device_daemons/voice/evaluation.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace igms::voice {

std::vector<CorpusItem> BuildCorpus(const std::vector<Voice>& voices,
                                    const std::vector<std::string>& out_of_vocabulary,
                                    int oov_voices_per_word) {
  std::vector<CorpusItem> corpus;
  for (const Voice& voice : voices) {
    for (const CommandInfo& info : AllCommands()) {
      CorpusItem item;
      item.speech = {std::string(info.phrase), voice.name, voice.words_per_minute};
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
      item.speech = {word, voice.name, voice.words_per_minute};
      corpus.push_back(item);
    }
  }
  return corpus;
}

double EvaluationReport::decode_ms_quantile(double q) const {
  if (decode_ms.empty()) return 0.0;
  std::vector<double> sorted = decode_ms;
  std::sort(sorted.begin(), sorted.end());
  const size_t i = static_cast<size_t>(std::lround(q * (sorted.size() - 1)));
  return sorted[std::min(i, sorted.size() - 1)];
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
    out << "  \"" << r.item.speech.text << "\" " << r.item.speech.voice << " "
        << r.item.speech.words_per_minute << " wpm in " << StateName(r.item.state) << ": "
        << (r.recognition.accepted
                ? "accepted as \"" + std::string(Phrase(*r.recognition.command)) + "\""
                : "rejected, " + std::string(RejectReasonName(r.recognition.reason)))
        << " (heard \"" << r.recognition.hypothesis << "\", confidence " << r.recognition.confidence
        << ", score " << r.recognition.score_per_frame << ", uncovered "
        << r.recognition.uncovered_speech_ms << " ms"
        << (r.recognition.english.empty() ? "" : ", English \"" + r.recognition.english + "\"")
        << ")\n";
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

std::optional<EvaluationReport> Evaluate(Recognizer& recognizer,
                                         const std::vector<CorpusItem>& corpus,
                                         std::string* error) {
  EvaluationReport report;
  for (const CorpusItem& item : corpus) {
    std::optional<Audio> audio = Synthesize(item.speech, error);
    if (!audio) return std::nullopt;
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

}  // namespace igms::voice
