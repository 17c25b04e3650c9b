#include "device_daemons/voice/adaptation.h"

#include <pocketsphinx.h>
#include <sphinxbase/err.h>
#include <sphinxbase/fe.h>
#include <stdlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "common/process/process.h"
#include "device_daemons/voice/grammar.h"
#include "device_daemons/voice/recognizer.h"

namespace igms::voice {
namespace fs = std::filesystem;
namespace {

constexpr int kMinUtterances = 10;

// The words of a transcript, lower case; punctuation other than apostrophes separates them
// ("Move the pointer, please." is what an operator's list may well say).
std::vector<std::string> Words(const std::string& text) {
  std::string cleaned = text;
  for (char& c : cleaned) {
    const auto u = static_cast<unsigned char>(c);
    c = std::isalpha(u) || c == '\'' ? static_cast<char>(std::tolower(u)) : ' ';
  }
  std::istringstream in(cleaned);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

// feat.params: one "-key value" a line; the feature settings the model was trained with.
std::map<std::string, std::string> ReadFeatParams(const fs::path& path) {
  std::map<std::string, std::string> out;
  std::ifstream in(path);
  for (std::string key, value; in >> key >> value;) out[key] = value;
  return out;
}

// Computes the front end's cepstra for each utterance into <dir>/<id>.mfc (sphinx's feature
// file: an int32 count of values, then that many float32s), with the decoder's own settings.
std::string WriteFeatures(const std::vector<AdaptationUtterance>& utterances,
                          const std::string& model_dir, const fs::path& dir,
                          std::vector<std::string>* ids) {
  err_set_logfp(nullptr);  // pocketsphinx logs every loading step to stderr
  std::vector<std::string> args = {"-hmm", model_dir + "/en-us", "-dict",
                                   model_dir + "/cmudict-en-us.dict"};
  for (const std::string& a : FrontEndArgs()) args.push_back(a);
  std::vector<char*> argv;
  argv.reserve(args.size());
  for (std::string& a : args) argv.push_back(a.data());
  cmd_ln_t* config =
      cmd_ln_parse_r(nullptr, ps_args(), static_cast<int32>(argv.size()), argv.data(), FALSE);
  if (config == nullptr) return "pocketsphinx rejected the front end's configuration";
  ps_decoder_t* decoder = ps_init(config);
  if (decoder == nullptr) {
    cmd_ln_free_r(config);
    return "cannot load the acoustic model from " + model_dir + "/en-us";
  }
  fe_t* fe = ps_get_fe(decoder);
  const int width = fe_get_output_size(fe);
  std::string error;
  for (size_t i = 0; i < utterances.size() && error.empty(); ++i) {
    const std::vector<int16_t>& samples = utterances[i].audio.samples;
    mfcc_t** cepstra = nullptr;
    int32 frames = 0;
    std::vector<mfcc_t> last(static_cast<size_t>(width));
    int32 last_frames = 0;
    fe_start_utt(fe);
    if (fe_process_utt(fe, samples.data(), samples.size(), &cepstra, &frames) < 0 ||
        fe_end_utt(fe, last.data(), &last_frames) < 0) {
      error = "the front end failed on utterance " + std::to_string(i + 1);
    }
    std::vector<float> values;
    for (int32 f = 0; f < frames; ++f) values.insert(values.end(), cepstra[f], cepstra[f] + width);
    if (last_frames > 0) values.insert(values.end(), last.begin(), last.end());
    if (cepstra) fe_free_2d(cepstra);
    const std::string id = "u" + std::to_string(i + 1);
    ids->push_back(id);
    std::ofstream out(dir / (id + ".mfc"), std::ios::binary);
    const auto count = static_cast<int32_t>(values.size());
    out.write(reinterpret_cast<const char*>(&count), sizeof count);
    out.write(reinterpret_cast<const char*>(values.data()),
              static_cast<std::streamsize>(values.size() * sizeof(float)));
    if (!out) error = "cannot write features to " + dir.string();
  }
  ps_free(decoder);
  cmd_ln_free_r(config);
  return error;
}

// The dictionary bw aligns with: the model's first pronunciation of every word said, and the
// commands' own ("unfreeze" is not in the CMU dictionary).
std::string WriteDictionary(const std::vector<AdaptationUtterance>& utterances,
                            const std::string& model_dir, const fs::path& path) {
  auto entries = LoadDictionary(model_dir + "/cmudict-en-us.dict");
  if (!entries.ok()) return entries.error();
  std::map<std::string, std::vector<std::string>> phones;
  for (const Pronunciation& p : *entries) phones.emplace(p.word, p.phones);
  for (const Pronunciation& p : CommandPronunciations()) phones.emplace(p.word, p.phones);
  std::set<std::string> said;
  for (const AdaptationUtterance& u : utterances) {
    for (const std::string& w : Words(u.text)) said.insert(w);
  }
  std::ofstream out(path);
  for (const std::string& w : said) {
    auto it = phones.find(w);
    if (it == phones.end()) return "no pronunciation for '" + w + "' in the dictionary";
    out << w;
    for (const std::string& ph : it->second) out << ' ' << ph;
    out << '\n';
  }
  return out ? "" : "cannot write " + path.string();
}

uint32_t Swap(uint32_t v) { return __builtin_bswap32(v); }

// pocketsphinx ships quantised mixture weights ("sendump": 8-bit negated logs, base 1.0001,
// shifted); bw and map_adapt read sphinx's float mixture_weights file. This undoes the
// quantisation.
std::string SendumpToMixtureWeights(const fs::path& in_path, const fs::path& out_path) {
  std::ifstream in(in_path, std::ios::binary);
  if (!in) return "cannot read " + in_path.string();
  bool swap = false;
  auto read_u32 = [&](uint32_t* v) {
    in.read(reinterpret_cast<char*>(v), 4);
    if (swap) *v = Swap(*v);
    return static_cast<bool>(in);
  };
  int shift = 10, features = 1, clusters = 0;
  for (bool first = true;; first = false) {
    uint32_t length = 0;
    if (!read_u32(&length)) return "truncated header in " + in_path.string();
    if (first && length > 65536) {
      swap = true;
      length = Swap(length);
    }
    if (length == 0) break;
    if (length > 65536) return "bad header in " + in_path.string();
    std::string line(length, '\0');
    in.read(line.data(), length);
    std::istringstream fields(line.c_str());
    std::string key;
    int value = 0;
    if (fields >> key >> value) {
      if (key == "mixw_shift") shift = value;
      if (key == "feature_count") features = value;
      if (key == "cluster_count") clusters = value;
    }
  }
  if (clusters != 0) return "clustered mixture weights are not supported: " + in_path.string();
  uint32_t densities = 0, senones = 0;
  if (!read_u32(&densities) || !read_u32(&senones) || densities == 0 || senones == 0 ||
      densities > 4096 || senones > 1000000 || features < 1 || features > 8) {
    return "bad dimensions in " + in_path.string();
  }
  std::vector<float> weights(static_cast<size_t>(senones) * features * densities);
  std::vector<unsigned char> row(senones);
  for (int f = 0; f < features; ++f) {
    for (uint32_t d = 0; d < densities; ++d) {
      in.read(reinterpret_cast<char*>(row.data()), senones);
      if (!in) return "truncated data in " + in_path.string();
      for (uint32_t s = 0; s < senones; ++s) {
        const double log_weight = -static_cast<double>(row[s] << shift);
        weights[(static_cast<size_t>(s) * features + f) * densities + d] =
            static_cast<float>(std::pow(1.0001, log_weight));
      }
    }
  }
  std::ofstream out(out_path, std::ios::binary);
  // sphinx's binary header: text lines, "endhdr" padded so the data starts 4-byte aligned,
  // a byte-order word, then the dimensions and the count.
  out << "s3\nversion 1.0\n  endhdr\n";
  const uint32_t header[] = {0x11223344u, senones, static_cast<uint32_t>(features), densities,
                             static_cast<uint32_t>(weights.size())};
  out.write(reinterpret_cast<const char*>(header), sizeof header);
  out.write(reinterpret_cast<const char*>(weights.data()),
            static_cast<std::streamsize>(weights.size() * sizeof(float)));
  return out ? "" : "cannot write " + out_path.string();
}

bool IsBinaryMdef(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[4] = {};
  in.read(magic, 4);
  return std::memcmp(magic, "BMDF", 4) == 0 || std::memcmp(magic, "FDMB", 4) == 0;
}

class WorkDir {
 public:
  explicit WorkDir(const std::string& keep) : keep_(!keep.empty()) {
    if (keep_) {
      path_ = keep;
      fs::create_directories(path_, error_);
      return;
    }
    std::string tmpl = (fs::temp_directory_path() / "igms-adapt-XXXXXX").string();
    if (mkdtemp(tmpl.data()) != nullptr) path_ = tmpl;
  }
  ~WorkDir() {
    std::error_code ec;
    if (!keep_ && !path_.empty()) fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }
  bool ok() const { return !path_.empty() && !error_; }

 private:
  bool keep_;
  fs::path path_;
  std::error_code error_;
};

// The source model as sphinxtrain's programs read it: a text model definition and float
// mixture weights, made in the working folder when the model has only the binary and
// quantised forms pocketsphinx loads.
struct SourceModel {
  fs::path dir;  // <model_dir>/en-us
  fs::path mdef, mixture_weights;
  std::map<std::string, std::string> feat_params;

  // The arguments bw and map_adapt share: the model's files and its tying.
  std::vector<std::string> Args() const {
    const auto kind = feat_params.find("-model");
    const std::string tying = kind == feat_params.end() ? "cont" : kind->second;
    return {"-moddeffn", mdef.string(),
            "-ts2cbfn",  "." + tying + ".",
            "-meanfn",   (dir / "means").string(),
            "-varfn",    (dir / "variances").string(),
            "-mixwfn",   mixture_weights.string(),
            "-tmatfn",   (dir / "transition_matrices").string()};
  }
};

std::string PrepareSource(const std::string& model_dir, const fs::path& work, SourceModel* model) {
  model->dir = fs::path(model_dir) / "en-us";
  model->feat_params = ReadFeatParams(model->dir / "feat.params");
  if (model->feat_params.count("-lda")) return "models with an LDA transform are not supported";
  model->mdef = model->dir / "mdef";
  if (IsBinaryMdef(model->mdef)) {
    model->mdef = work / "mdef.txt";
    if (std::string e = RunProgram({"pocketsphinx_mdef_convert", "-text",
                                    (model->dir / "mdef").string(), model->mdef.string()},
                                   (work / "mdef_convert.log").string());
        !e.empty())
      return e;
  }
  model->mixture_weights = model->dir / "mixture_weights";
  if (fs::exists(model->mixture_weights)) return "";
  model->mixture_weights = work / "mixture_weights";
  return SendumpToMixtureWeights(model->dir / "sendump", model->mixture_weights);
}

// Features, transcripts and dictionary for bw, in the working folder.
std::string PrepareSpeech(const std::vector<AdaptationUtterance>& utterances,
                          const std::string& model_dir, const fs::path& work) {
  fs::create_directories(work / "features");
  std::vector<std::string> ids;
  if (std::string e = WriteFeatures(utterances, model_dir, work / "features", &ids); !e.empty())
    return e;
  std::ofstream ctl(work / "utterances.ctl"), lsn(work / "transcripts.txt");
  for (size_t i = 0; i < ids.size(); ++i) {
    ctl << ids[i] << '\n';
    lsn << "<s>";
    for (const std::string& w : Words(utterances[i].text)) lsn << ' ' << w;
    lsn << " </s> (" << ids[i] << ")\n";
  }
  if (!ctl || !lsn) return "cannot write the transcripts in " + work.string();
  return WriteDictionary(utterances, model_dir, work / "words.dict");
}

// Baum-Welch counts of the speech against the source model, into <work>/counts.
std::string Count(const SourceModel& model, const fs::path& tools, const fs::path& work) {
  fs::create_directories(work / "counts");
  std::vector<std::string> bw = {(tools / "bw").string()};
  for (std::string& a : model.Args()) bw.push_back(std::move(a));
  bw.insert(bw.end(),
            {"-dictfn", (work / "words.dict").string(), "-fdictfn",
             (model.dir / "noisedict").string(), "-ctlfn", (work / "utterances.ctl").string(),
             "-lsnfn", (work / "transcripts.txt").string(), "-cepdir", (work / "features").string(),
             "-cepext", "mfc", "-accumdir", (work / "counts").string()});
  for (const char* key : {"-feat", "-svspec", "-cmn", "-agc", "-varnorm", "-cmninit"}) {
    const auto it = model.feat_params.find(key);
    if (it != model.feat_params.end()) bw.insert(bw.end(), {key, it->second});
  }
  return RunProgram(bw, (work / "bw.log").string());
}

// map_adapt writes the adapted parameters into <folder>/en-us; the rest of the model folder
// is copied or linked beside them.
std::string WriteModel(const SourceModel& model, const AdaptationOptions& options,
                       const fs::path& work, const fs::path& folder) {
  const fs::path adapted = folder / "en-us";
  fs::create_directories(adapted);
  std::vector<std::string> map = {(fs::path(options.sphinxtrain_dir) / "map_adapt").string()};
  for (std::string& a : model.Args()) map.push_back(std::move(a));
  map.insert(map.end(),
             {"-accumdir", (work / "counts").string(), "-mapmeanfn", (adapted / "means").string(),
              "-mapvarfn", (adapted / "variances").string(), "-mapmixwfn",
              (adapted / "mixture_weights").string(), "-maptmatfn",
              (adapted / "transition_matrices").string()});
  if (std::string e = RunProgram(map, (work / "map_adapt.log").string()); !e.empty()) return e;
  std::error_code ec;
  for (const char* file : {"mdef", "feat.params", "noisedict"}) {
    fs::copy_file(model.dir / file, adapted / file, ec);
    if (ec) return "cannot copy " + (model.dir / file).string() + ": " + ec.message();
  }
  // The dictionary and language models are the source's, unchanged: linked, not copied.
  for (const char* file : {"cmudict-en-us.dict", "en-us-phone.lm.bin", "en-us.lm.bin"}) {
    const fs::path source = fs::path(options.model_dir) / file;
    if (fs::exists(source)) fs::create_symlink(fs::absolute(source), folder / file, ec);
    if (ec) return "cannot link " + source.string() + ": " + ec.message();
  }
  return "";
}

std::string WriteRecord(const std::vector<AdaptationUtterance>& utterances,
                        const AdaptationOptions& options, const fs::path& folder) {
  double seconds = 0.0;
  for (const AdaptationUtterance& u : utterances) seconds += u.audio.seconds();
  std::ofstream record(folder / kAdaptationRecord);
  record << "adapted from: " << fs::absolute(options.model_dir).string() << "\n"
         << "utterances: " << utterances.size() << "\n"
         << "speech seconds: " << seconds << "\n";
  return record ? "" : "cannot write " + (folder / kAdaptationRecord).string();
}

std::string Adapt(const std::vector<AdaptationUtterance>& utterances,
                  const AdaptationOptions& options, const fs::path& work) {
  SourceModel model;
  if (std::string e = PrepareSource(options.model_dir, work, &model); !e.empty()) return e;
  if (std::string e = PrepareSpeech(utterances, options.model_dir, work); !e.empty()) return e;
  if (std::string e = Count(model, options.sphinxtrain_dir, work); !e.empty()) return e;
  // Built beside the destination and moved into place at the end, so a failure leaves
  // whatever model was there before.
  fs::path out = fs::absolute(options.out_dir).lexically_normal();
  if (!out.has_filename()) out = out.parent_path();  // "DIR/": the staging folder beside DIR
  const fs::path staged = out.string() + ".partial";
  std::error_code ec;
  fs::remove_all(staged, ec);
  std::string error = WriteModel(model, options, work, staged);
  if (error.empty()) error = WriteRecord(utterances, options, staged);
  if (error.empty()) {
    fs::remove_all(out, ec);
    fs::rename(staged, out, ec);
    if (ec) error = "cannot move the adapted model to " + out.string() + ": " + ec.message();
  }
  fs::remove_all(staged, ec);
  return error;
}

}  // namespace

const std::vector<std::string>& EnrolmentPrompts() {
  static const std::vector<std::string> prompts = [] {
    std::vector<std::string> out;
    for (const CommandInfo& info : AllCommands()) out.emplace_back(info.phrase);
    // Sentences of the lab's own work, which between them say every phone of the model.
    for (const char* s : {"move the pointer to the top of the pipe",
                          "the camera platform turns slowly to the left",
                          "mark four points around the edge of the block",
                          "the valve on the far wall looks rusty",
                          "put the cursor just above the joint",
                          "the tank floor is covered with thick sludge",
                          "check the depth with the ultrasonic ranger",
                          "the robot arm should avoid the hot vessel",
                          "draw the outline in green over the video",
                          "a yellow cable hangs from the ceiling",
                          "the thin rod leans against the support beam",
                          "zoom out and show me the whole room",
                          "the boiler pipe bends sharply near the pump",
                          "the wheel is jammed by a heavy chain",
                          "we measured each object twice to be sure",
                          "judge the shape by looking at both images",
                          "the shiny drum sits behind the orange crate",
                          "please hold the joystick still for a moment",
                          "this view gives a clear sight of the bottom",
                          "they found three loose bolts under the hatch",
                          "the voice was quiet but the words were clear",
                          "the operator pushed the trigger with her thumb",
                          "a small leak could spoil the whole measurement",
                          "the pressure gauge reads nearly zero",
                          "choose the nearest surface inside the beam",
                          "the vision system finds the exact pose",
                          "go back and check the corner again",
                          "a thousand points were matched in the pair",
                          "the light was dim and the picture was noisy",
                          "use the left button to toggle the display"}) {
      out.emplace_back(s);
    }
    return out;
  }();
  return prompts;
}

bool AdaptationOptions::Check(std::string* error) const {
  auto fail = [&](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  if (out_dir.empty()) return fail("no folder given for the adapted model");
  std::error_code ec;
  if (fs::exists(out_dir, ec) && fs::equivalent(out_dir, model_dir, ec)) {
    return fail("the adapted model must not replace the model it adapts (" + model_dir + ")");
  }
  if (!fs::is_directory(fs::path(model_dir) / "en-us")) {
    return fail("no acoustic model folder " + model_dir + "/en-us");
  }
  for (const char* tool : {"bw", "map_adapt"}) {
    if (!fs::exists(fs::path(sphinxtrain_dir) / tool)) {
      return fail("sphinxtrain's " + std::string(tool) + " is not in " + sphinxtrain_dir +
                  " (Debian's package sphinxtrain)");
    }
  }
  return true;
}

AdaptationReport AdaptModel(const std::vector<AdaptationUtterance>& utterances,
                            const AdaptationOptions& options) {
  AdaptationReport report;
  if (!options.Check(&report.error)) return report;
  if (utterances.size() < static_cast<size_t>(kMinUtterances)) {
    report.error = "adaptation needs at least " + std::to_string(kMinUtterances) +
                   " utterances, got " + std::to_string(utterances.size());
    return report;
  }
  for (size_t i = 0; i < utterances.size(); ++i) {
    const AdaptationUtterance& u = utterances[i];
    const std::string which = "utterance " + std::to_string(i + 1);
    if (u.audio.sample_rate != kModelSampleRate) {
      report.error = which + " is at " + std::to_string(u.audio.sample_rate) + " Hz, not " +
                     std::to_string(kModelSampleRate);
    } else if (u.audio.seconds() < 0.1) {
      report.error = which + " is shorter than 0.1 s";
    } else if (Words(u.text).empty()) {
      report.error = which + " has no transcript";
    }
    if (!report.ok()) return report;
    report.seconds += u.audio.seconds();
  }
  report.utterances = static_cast<int>(utterances.size());
  WorkDir work(options.work_dir);
  if (!work.ok()) {
    report.error = "cannot create a working folder for the adaptation";
    return report;
  }
  try {
    report.error = Adapt(utterances, options, work.path());
  } catch (const fs::filesystem_error& e) {
    report.error = e.what();
  }
  return report;
}

bool IsAdaptedModel(const std::string& model_dir) {
  return fs::is_regular_file(fs::path(model_dir) / kAdaptationRecord);
}

RecognizerOptions EnrolledRecognizerOptions(const std::string& model_dir) {
  RecognizerOptions options;
  options.model_dir = model_dir;
  options.decoys.max_per_command = 15;
  options.grammar.decoy_weight = 1e-10;
  options.min_confidence = 0.01;
  options.fillers.count = 10000;
  options.fillers.weight = 1e-2;
  return options;
}

RecognizerOptions RecognizerOptionsFor(const std::string& model_dir) {
  if (IsAdaptedModel(model_dir)) return EnrolledRecognizerOptions(model_dir);
  RecognizerOptions options;
  options.model_dir = model_dir;
  return options;
}

}  // namespace igms::voice
