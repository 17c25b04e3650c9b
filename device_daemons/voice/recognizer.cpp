// The only file that includes pocketsphinx.h: it cannot share a translation unit with
// OpenCV's headers (both define int64), so it stays behind the Impl.
#include "device_daemons/voice/recognizer.h"

#include <pocketsphinx.h>
#include <sphinxbase/err.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <sstream>

#include "device_daemons/voice/audio.h"

namespace igms::voice {
namespace {

std::string Join(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : " ") + s;
  return out;
}

bool IsFiller(const std::string& token) {
  return token.empty() || token == "<s>" || token == "</s>" || token == "<sil>" ||
         token.front() == '[' || token.front() == '+';
}

// "word(2)" is the decoder's name for a word's second pronunciation.
std::string BaseWord(const char* token) {
  std::string word = token ? token : "";
  if (const size_t paren = word.find('('); paren != std::string::npos) word.resize(paren);
  return word;
}

}  // namespace

const std::vector<std::string>& FrontEndArgs() {
  // Noise removal hurt synthetic speech; dither with a fixed seed keeps digital silence from
  // upsetting the features and makes every result repeatable.
  static const std::vector<std::string> args = {"-remove_noise", "no",    "-dither",
                                                "yes",           "-seed", "1"};
  return args;
}

std::string_view RejectReasonName(RejectReason reason) {
  switch (reason) {
    case RejectReason::kNone:
      return "accepted";
    case RejectReason::kNoSpeech:
      return "no_speech";
    case RejectReason::kOutOfVocabulary:
      return "out_of_vocabulary";
    case RejectReason::kNotValidInState:
      return "not_valid_in_state";
    case RejectReason::kLowConfidence:
      return "low_confidence";
    case RejectReason::kUnexplainedSpeech:
      return "unexplained_speech";
    case RejectReason::kUnstable:
      return "unstable";
    case RejectReason::kOtherWord:
      return "other_word";
  }
  return "unknown";
}

bool RecognizerOptions::Check(std::string* error) const {
  if (model_dir.empty()) {
    if (error) *error = "recognizer model_dir is empty";
    return false;
  }
  if (!(max_uncovered_speech_ms >= 0.0)) {
    if (error) *error = "recognizer max_uncovered_speech_ms must be >= 0";
    return false;
  }
  if (min_agreement < 0 || min_agreement > static_cast<int>(perturbations.size()) ||
      !std::all_of(perturbations.begin(), perturbations.end(),
                   [](double f) { return f >= 0.5 && f <= 2.0; })) {
    if (error)
      *error = "recognizer perturbations must be in [0.5, 2], min_agreement at most their number";
    return false;
  }
  if (decoder_args.size() % 2 != 0) {
    if (error) *error = "recognizer decoder_args must come in pairs";
    return false;
  }
  if (!(min_confidence >= 0.0 && min_confidence <= 1.0)) {
    if (error) *error = "recognizer min_confidence must be in [0, 1]";
    return false;
  }
  return decoys.Check(error) && fillers.Check(error) && grammar.Check(error);
}

struct Recognizer::Impl {
  RecognizerOptions options;
  cmd_ln_t* config = nullptr;
  ps_decoder_t* decoder = nullptr;
  OperatorState state = OperatorState::kVerification;
  std::map<OperatorState, std::string> grammars;
  size_t decoys = 0;
  size_t fillers = 0;
  std::string verification_grammar;

  ~Impl() {
    if (decoder) ps_free(decoder);
    if (config) cmd_ln_free_r(config);
  }

  bool Load(std::string* error) {
    // pocketsphinx logs every step of model loading to stderr; the daemon logs what matters.
    err_set_logfp(nullptr);
    const std::string hmm = options.model_dir + "/en-us";
    const std::string dict = options.model_dir + "/cmudict-en-us.dict";
    auto words = LoadDictionary(dict);
    if (!words.ok()) return Fail(error, words.error());
    // Beams narrower than pocketsphinx's defaults (1e-48, 7e-29, 1e-48): speech far from
    // every command then more often finds no path at all (tuned on the tuning voices).
    std::vector<std::string> args = {"-hmm",         hmm,    "-dict", dict,    "-bestpath", "no",
                                     "-allphone_ci", "yes",  "-beam", "1e-20", "-pbeam",    "1e-20",
                                     "-wbeam",       "1e-15"};
    args.insert(args.end(), FrontEndArgs().begin(), FrontEndArgs().end());
    // pocketsphinx refuses an argument given twice: one in decoder_args replaces the built-in.
    for (size_t i = 0; i < options.decoder_args.size(); i += 2) {
      for (size_t j = 0; j + 1 < args.size(); j += 2) {
        if (args[j] == options.decoder_args[i]) {
          args.erase(args.begin() + static_cast<std::ptrdiff_t>(j),
                     args.begin() + static_cast<std::ptrdiff_t>(j + 2));
          break;
        }
      }
    }
    args.insert(args.end(), options.decoder_args.begin(), options.decoder_args.end());
    std::vector<char*> argv;
    argv.reserve(args.size());
    for (std::string& a : args) argv.push_back(a.data());
    config = cmd_ln_parse_r(nullptr, ps_args(), static_cast<int32>(argv.size()), argv.data(), TRUE);
    if (config == nullptr) {
      if (error) *error = "pocketsphinx rejected its configuration";
      return false;
    }
    decoder = ps_init(config);
    if (decoder == nullptr) {
      if (error) *error = "cannot load the pocketsphinx acoustic model from " + hmm;
      return false;
    }
    // Phone tokens and the command words go into the dictionary only.
    std::vector<Pronunciation> phones;
    for (const std::string& phone : ModelPhones()) phones.push_back({PhoneToken(phone), {phone}});
    if (!AddWords(phones, FALSE, error)) return false;
    const std::string lm_path = options.model_dir + "/en-us.lm.bin";
    if (!AddWords(CommandPronunciations(), TRUE, error)) return false;
    if (!AddWords(AlternativePronunciations(), TRUE, error)) return false;
    // The general English model ranks dictionary words by how common they are.
    ngram_model_t* lm =
        ngram_model_read(config, lm_path.c_str(), NGRAM_AUTO, ps_get_logmath(decoder));
    if (lm == nullptr) {
      if (error) *error = "cannot read the language model " + lm_path;
      return false;
    }
    ngram_model_apply_weights(lm, 1.0, 1.0);  // plain probabilities, not decoding scores
    logmath_t* lmath = ps_get_logmath(decoder);
    auto log10_unigram = [&](const std::string& word) {
      if (ngram_wid(lm, word.c_str()) == ngram_unknown_wid(lm)) return -99.0;
      return logmath_log_to_log10(lmath, ngram_score(lm, word.c_str(), nullptr));
    };
    const std::vector<Pronunciation> decoy_words =
        SelectDecoys(*words, options.decoys, log10_unigram);
    const std::vector<Pronunciation> filler_words =
        SelectFillerWords(*words, options.fillers, options.decoys, log10_unigram);
    fillers = filler_words.size();
    ngram_model_free(lm);
    decoys = decoy_words.size();
    for (OperatorState s : AllStates()) {
      grammars[s] = BuildGrammar(s, decoy_words, options.grammar);
      if (ps_set_jsgf_string(decoder, std::string(StateName(s)).c_str(), grammars[s].c_str()) < 0) {
        if (error)
          *error = "pocketsphinx rejected the grammar of state " + std::string(StateName(s));
        return false;
      }
    }
    if (!filler_words.empty()) {
      // A search takes its beams from the configuration when it is made. This one gets
      // pocketsphinx's own wide beams: its words pay their weight only at their last phone,
      // and narrow beams would let a cheap prefix prune the command before then.
      const double beams[3] = {cmd_ln_float_r(config, "-beam"), cmd_ln_float_r(config, "-pbeam"),
                               cmd_ln_float_r(config, "-wbeam")};
      cmd_ln_set_float_r(config, "-beam", 1e-48);
      cmd_ln_set_float_r(config, "-pbeam", 1e-48);
      cmd_ln_set_float_r(config, "-wbeam", 7e-29);
      verification_grammar = BuildVerificationGrammar(filler_words, options.fillers.weight);
      const int rc = ps_set_jsgf_string(decoder, "verify", verification_grammar.c_str());
      cmd_ln_set_float_r(config, "-beam", beams[0]);
      cmd_ln_set_float_r(config, "-pbeam", beams[1]);
      cmd_ln_set_float_r(config, "-wbeam", beams[2]);
      if (rc < 0) {
        if (error) *error = "pocketsphinx rejected the verification grammar";
        return false;
      }
    }
    const std::string phone_lm = options.model_dir + "/en-us-phone.lm.bin";
    if (ps_set_allphone_file(decoder, "phones", phone_lm.c_str()) < 0) {
      if (error) *error = "cannot load the phone language model " + phone_lm;
      return false;
    }
    // The first decode of each search builds its tables (about two seconds); do it now so
    // the operator's first command is not the slow one.
    const std::vector<int16_t> warm_up(kModelSampleRate / 2, 0);
    for (OperatorState s : AllStates()) {
      state = s;
      Decode(warm_up);
    }
    PhoneLoopScore(warm_up, Span{});
    if (fillers > 0) Verify(warm_up);
    state = options.initial_state;
    return true;
  }

  // Adds the words the dictionary lacks.
  bool AddWords(const std::vector<Pronunciation>& words, int update, std::string* error) {
    for (const Pronunciation& p : words) {
      if (char* known = ps_lookup_word(decoder, p.word.c_str())) {
        ckd_free(known);
        continue;
      }
      if (ps_add_word(decoder, p.word.c_str(), Join(p.phones).c_str(), update) < 0) {
        if (error) *error = "cannot add the word '" + p.word + "' to the dictionary";
        return false;
      }
    }
    return true;
  }

  static double UncoveredSpeechMs(std::span<const int16_t> samples, int first, int last,
                                  double floor_db) {
    constexpr size_t kFrame = kModelSampleRate / 100;
    std::vector<double> db;
    for (size_t i = 0; i + kFrame <= samples.size(); i += kFrame) {
      db.push_back(RmsDbfs(samples.subspan(i, kFrame)));
    }
    if (db.empty()) return 0.0;
    const double floor = std::max(-50.0, *std::max_element(db.begin(), db.end()) - floor_db);
    int uncovered = 0;
    for (int f = 0; f < static_cast<int>(db.size()); ++f) {
      if (db[f] > floor && (f < first - 2 || f > last + 2)) ++uncovered;
    }
    return uncovered * 10.0;
  }

  struct Span {
    int first = 0, last = -1;  // frames of the command word
    int32 ascr = 0;            // its acoustic score
  };

  // Acoustic score of the free phone decoding over the frames of `span`: a phone segment
  // counts in proportion to its overlap.
  double PhoneLoopScore(std::span<const int16_t> samples, const Span& span) {
    ps_set_search(decoder, "phones");
    ps_start_utt(decoder);
    ps_process_raw(decoder, samples.data(), samples.size(), FALSE, TRUE);
    ps_end_utt(decoder);
    double total = 0.0;
    for (ps_seg_t* seg = ps_seg_iter(decoder); seg; seg = ps_seg_next(seg)) {
      int sf = 0, ef = 0;
      ps_seg_frames(seg, &sf, &ef);
      int32 ascr = 0, lscr = 0, lback = 0;
      ps_seg_prob(seg, &ascr, &lscr, &lback);
      const int overlap = std::min(ef, span.last) - std::max(sf, span.first) + 1;
      if (overlap > 0) total += static_cast<double>(ascr) * overlap / (ef - sf + 1);
    }
    return total;
  }

  // How many of the perturbed playbacks decode as exactly `token` in the current state.
  int Agreement(std::span<const int16_t> samples, const std::string& token) {
    int agree = 0;
    for (double f : options.perturbations) {
      // Read at f times the rate: f times faster, every frequency f times higher.
      const std::vector<int16_t> played =
          Resample(samples, static_cast<int>(std::lround(kModelSampleRate * f)), kModelSampleRate);
      ps_set_search(decoder, std::string(StateName(state)).c_str());
      if (played.empty() || ps_start_utt(decoder) < 0) continue;
      ps_process_raw(decoder, played.data(), played.size(), FALSE, TRUE);
      ps_end_utt(decoder);
      int32 score = 0;
      const char* hyp = ps_get_hyp(decoder, &score);
      agree += hyp != nullptr && token == hyp;
    }
    return agree;
  }

  // The best of every command and the filler words for the whole utterance; empty when no
  // path reached the end.
  std::string Verify(std::span<const int16_t> samples) {
    ps_set_search(decoder, "verify");
    if (samples.empty() || ps_start_utt(decoder) < 0) return {};
    ps_process_raw(decoder, samples.data(), samples.size(), FALSE, TRUE);
    ps_end_utt(decoder);
    int32 score = 0;
    std::vector<std::string> words;
    if (ps_get_hyp(decoder, &score) == nullptr) return {};
    for (ps_seg_t* seg = ps_seg_iter(decoder); seg; seg = ps_seg_next(seg)) {
      const std::string word = BaseWord(ps_seg_word(seg));
      if (!IsFiller(word)) words.push_back(word);
    }
    return Join(words);
  }

  Recognition Decode(std::span<const int16_t> samples) {
    Recognition r;
    r.state = state;
    r.audio_seconds = static_cast<double>(samples.size()) / kModelSampleRate;
    const auto start = std::chrono::steady_clock::now();
    ps_set_search(decoder, std::string(StateName(state)).c_str());
    std::vector<std::string> tokens;
    Span span;
    bool decoded = false;
    if (!samples.empty() && ps_start_utt(decoder) >= 0) {
      ps_process_raw(decoder, samples.data(), samples.size(), FALSE, TRUE);
      ps_end_utt(decoder);
      int32 score = 0;
      decoded = ps_get_hyp(decoder, &score) != nullptr;
      for (ps_seg_t* seg = decoded ? ps_seg_iter(decoder) : nullptr; seg; seg = ps_seg_next(seg)) {
        const std::string word = BaseWord(ps_seg_word(seg));
        if (IsFiller(word)) continue;
        tokens.push_back(word);
        ps_seg_frames(seg, &span.first, &span.last);
        int32 lscr = 0, lback = 0;
        ps_seg_prob(seg, &span.ascr, &lscr, &lback);
      }
      if (tokens.size() == 1)
        r.uncovered_speech_ms =
            UncoveredSpeechMs(samples, span.first, span.last, options.speech_floor_db);
      if (tokens.size() == 1 && span.last >= span.first)
        r.command_ms = 10.0 * (span.last - span.first + 1);
      if (tokens.size() == 1 && span.last >= span.first && options.min_confidence > 0.0) {
        const double loop = PhoneLoopScore(samples, span);
        r.score_per_frame = (span.ascr - loop) / (span.last - span.first + 1);
        r.confidence =
            1.0 /
            (1.0 + std::exp(-(r.score_per_frame - options.score_offset) / options.score_scale));
      }
    }
    r.hypothesis = Join(tokens);
    Classify(tokens, r);
    // Only a command that passed every other test is decoded again (it costs a decode each).
    if (r.accepted && options.min_agreement > 0) {
      r.agreement = Agreement(samples, tokens[0]);
      if (r.agreement < options.min_agreement) {
        r.accepted = false;
        r.reason = RejectReason::kUnstable;
        std::ostringstream why;
        why << "\"" << Phrase(*r.command) << "\" heard again at only " << r.agreement << " of "
            << options.perturbations.size() << " other playback speeds";
        r.message = why.str();
      }
    }
    if (r.accepted && fillers > 0) {
      r.verification = Verify(samples);
      if (r.verification != tokens[0]) {
        r.accepted = false;
        r.reason = RejectReason::kOtherWord;
        r.message = "\"" + std::string(Phrase(*r.command)) + "\" sounds more like \"" +
                    (r.verification.empty() ? std::string("nothing") : r.verification) + "\"";
      }
    }
    if (r.accepted && options.predict_state) state = PredictNextState(state, *r.command);
    r.decode_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return r;
  }

  void Classify(const std::vector<std::string>& tokens, Recognition& r) {
    if (tokens.empty()) {
      r.reason = RejectReason::kNoSpeech;
      r.message = "nothing recognised";
      return;
    }
    const std::optional<Command> command =
        tokens.size() == 1 ? CommandFromToken(tokens[0]) : std::nullopt;
    if (!command) {
      r.reason = RejectReason::kOutOfVocabulary;
      r.message = "not a command (heard \"" + r.hypothesis + "\")";
      return;
    }
    r.command = command;
    std::ostringstream why;
    if (!IsValid(state, *command)) {
      r.reason = RejectReason::kNotValidInState;
      why << "\"" << Phrase(*command) << "\" is not valid in state " << StateName(state);
    } else if (r.uncovered_speech_ms > options.max_uncovered_speech_ms) {
      r.reason = RejectReason::kUnexplainedSpeech;
      why << "\"" << Phrase(*command) << "\" leaves " << r.uncovered_speech_ms
          << " ms of speech unexplained";
    } else if (r.confidence < options.min_confidence) {
      r.reason = RejectReason::kLowConfidence;
      why << "\"" << Phrase(*command) << "\" confidence " << r.confidence << " is below "
          << options.min_confidence;
    } else {
      r.accepted = true;  // Decode() may still reject it, and predicts the next state
      return;
    }
    r.message = why.str();
  }
};

Recognizer::Recognizer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Recognizer::~Recognizer() = default;

std::unique_ptr<Recognizer> Recognizer::Create(const RecognizerOptions& options,
                                               std::string* error) {
  if (!options.Check(error)) return nullptr;
  auto impl = std::make_unique<Impl>();
  impl->options = options;
  if (!impl->Load(error)) return nullptr;
  return std::unique_ptr<Recognizer>(new Recognizer(std::move(impl)));
}

void Recognizer::SetState(OperatorState state) { impl_->state = state; }
OperatorState Recognizer::state() const { return impl_->state; }
Recognition Recognizer::Recognize(std::span<const int16_t> samples) {
  return impl_->Decode(samples);
}
const std::string& Recognizer::GrammarText(OperatorState state) const {
  return impl_->grammars.at(state);
}
size_t Recognizer::decoy_count() const { return impl_->decoys; }
size_t Recognizer::filler_count() const { return impl_->fillers; }
const std::string& Recognizer::VerificationGrammarText() const {
  return impl_->verification_grammar;
}

}  // namespace igms::voice
