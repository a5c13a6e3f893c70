#include "hunav/realism/realism.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "hunav/bounds.hpp"
#include "hunav/config_error.hpp"
#include "hunav/manager/agent_manager.hpp"
#include "hunav/thread_pool.hpp"
#include "hunav/yaml_reader.hpp"

namespace hunav::realism {

void readProtocol(const std::string& path, Protocol& protocol, SfmParams& sfm) {
  const YamlReader yaml(path);
  const YAML::Node& root = yaml.root();
  if (!root.IsMap()) yaml.fail(root, "", "expected a mapping of parameters");
  struct Key {
    const char* name;
    double* value;
    double lo, hi;
  };
  const Key keys[] = {{"goal_weight", &sfm.goal_weight, 0.0, 100.0},
                      {"obstacle_weight", &sfm.obstacle_weight, 0.0, 1000.0},
                      {"social_weight", &sfm.social_weight, 0.0, 100.0},
                      {"desired_speed", &protocol.desired_speed, -1.0, kMaxSpeed},
                      {"radius", &protocol.radius, 0.01, 2.0},
                      {"goal_radius", &protocol.goal_radius, 0.0, 10.0},
                      {"dt", &protocol.dt, 1e-4, 1.0},
                      {"cutoff", &protocol.cutoff, -1.0, 100.0},
                      {"goal_distance", &protocol.goal_distance, 0.01, 100.0},
                      {"overlap_distance", &protocol.overlap_distance, 0.0, 2.0}};
  for (const auto& kv : root) {
    const std::string name = kv.first.as<std::string>();
    const Key* key = nullptr;
    for (const Key& k : keys)
      if (name == k.name) key = &k;
    if (key == nullptr) {
      std::string known;
      for (const Key& k : keys) known += (known.empty() ? "" : ", ") + std::string(k.name);
      yaml.fail(kv.first, name, "unknown parameter (known: " + known + ")");
    }
    const double v = yaml.convert<double>(kv.second, name);
    if (!(v >= key->lo && v <= key->hi))
      yaml.fail(kv.second, name,
                "expected a number in [" + std::to_string(key->lo) + ", " + std::to_string(key->hi) + "]");
    *key->value = v;
  }
}

std::vector<Sample> extractSamples(const Dataset& d) {
  std::vector<Sample> out;
  for (const auto& [frame, people] : d.frames) {
    for (const auto& [id, p0] : people) {
      Sample s;
      s.id = id;
      s.first_frame = frame;
      bool complete = true;
      for (int k = 0; k < kWindow && complete; ++k) {
        const auto f = d.frames.find(frame + k);
        const auto q = f == d.frames.end() ? people.end() : f->second.find(id);
        complete = f != d.frames.end() && q != f->second.end();
        if (complete) s.truth[k] = q->second;
      }
      if (complete) out.push_back(s);
    }
  }
  return out;
}

double ade(const Prediction& pred, const Sample& s) {
  double sum = 0.0;
  for (int k = 0; k < kPredicted; ++k) sum += (pred[k] - s.truth[kObserved + k]).norm();
  return sum / kPredicted;
}

double fde(const Prediction& pred, const Sample& s) { return (pred.back() - s.truth.back()).norm(); }

Prediction predictConstantVelocity(const Sample& s, double interval) {
  const Vec2 step = s.truth[kObserved - 1] - s.truth[kObserved - 2];
  (void)interval;  // a constant velocity covers the same displacement every frame, whatever its length
  Prediction out;
  for (int k = 0; k < kPredicted; ++k) out[k] = s.truth[kObserved - 1] + static_cast<double>(k + 1) * step;
  return out;
}

double desiredSpeedOf(const Sample& s, double interval, const Protocol& p, const MotionModel& model) {
  if (p.desired_speed >= 0.0) return p.desired_speed;
  double path = 0.0;
  for (int k = 1; k < kObserved; ++k) path += (s.truth[k] - s.truth[k - 1]).norm();
  return std::min(model.desired_speed_factor * path / ((kObserved - 1) * interval), kMaxSpeed);
}

Vec2 goalOf(const Sample& s, double interval, const Protocol& p, GoalMode mode) {
  if (mode == GoalMode::Recorded) return s.truth.back();
  const Vec2 velocity = (s.truth[kObserved - 1] - s.truth[kObserved - 2]) / interval;
  return s.truth[kObserved - 1] + velocity * (p.goal_distance * kPredicted * interval);
}

namespace {

// The other people of one predicted frame interval: recorded at both of its frames.
struct Neighbour {
  int id;
  Vec2 position;  // at the interval's first frame
  Vec2 velocity;  // over the interval
};
using Neighbours = std::array<std::vector<Neighbour>, kPredicted>;

Neighbours neighboursOf(const Dataset& d, const Sample& s) {
  Neighbours out;
  for (int k = 0; k < kPredicted; ++k) {
    const std::int64_t f0 = s.first_frame + kObserved - 1 + k;
    const auto& a = d.frames.at(f0);
    const auto& b = d.frames.at(f0 + 1);
    for (const auto& [id, pa] : a) {
      if (id == s.id) continue;
      const auto pb = b.find(id);
      if (pb != b.end()) out[k].push_back(Neighbour{id, pa, (pb->second - pa) / d.frame_interval});
    }
  }
  return out;
}

int groupOf(const GroupIds* groups, int id) {
  if (groups == nullptr) return -1;
  const auto it = groups->find(id);
  return it == groups->end() ? -1 : it->second;
}

Prediction simulate(const Dataset& d, const Sample& s, const Neighbours& around, const Method& m, const Protocol& p,
                    const GroupIds* groups) {
  const double interval = d.frame_interval;
  const GroupIds* g = m.groups ? groups : nullptr;
  // The focal person as the manager sees it: a regular person, no obstacle points (the data sets
  // come without maps), HuNavSim's weights for HuNavSim's model.
  agent_state_t me{};
  me.id = s.id;
  me.type = agent_state_t::TYPE_PERSON;
  me.behavior = agent_state_t::BEH_REGULAR;
  me.group_id = groupOf(g, s.id);
  me.radius = p.radius;
  me.goal_radius = p.goal_radius;
  me.behavior_params.goal_force_factor = m.model.sfm.goal_weight;
  me.behavior_params.obstacle_force_factor = m.model.sfm.obstacle_weight;
  me.behavior_params.social_force_factor = m.model.sfm.social_weight;
  const double speed = desiredSpeedOf(s, interval, p, m.model);
  me.desired_speed = speed;
  const Vec2 goal = goalOf(s, interval, p, m.goal);
  const Vec2 start = s.truth[kObserved - 1];
  const Vec2 v0 = (s.truth[kObserved - 1] - s.truth[kObserved - 2]) / interval;
  me.x = start.x();
  me.y = start.y();
  me.vx = v0.x();
  me.vy = v0.y();
  me.yaw = v0.squaredNorm() > 0.0 ? angleOf(v0) : 0.0;
  // A frame interval split into n equal steps no longer than dt (0.4 s / 0.01 s = 40 steps exactly).
  const int n = std::max(1, static_cast<int>(std::ceil(interval / p.dt - 1e-9)));
  const double h = interval / n;
  // HuNavSim's SFM sums everybody within the manager's cut-off; the other models apply their own range.
  const double cutoff = m.model.isHunavDefault() && p.cutoff > 0.0 ? p.cutoff : -1.0;

  manager::StepSnapshot snap;
  snap.models.assign(1, m.model.isHunavDefault() ? nullptr : &m.model);
  Prediction out;
  for (int k = 0; k < kPredicted; ++k) {
    for (int i = 0; i < n; ++i) {
      const double t = i * h;
      const Vec2 pos(me.x, me.y);
      snap.agents.clear();
      SfmBody body;
      body.id = s.id;
      body.group_id = me.group_id;
      body.position = pos;
      body.velocity = Vec2(me.vx, me.vy);
      body.radius = p.radius;
      snap.agents.push_back(body);
      if (m.interaction) {
        for (const Neighbour& o : around[static_cast<std::size_t>(k)]) {
          SfmBody other;
          other.id = o.id;
          other.group_id = groupOf(g, o.id);
          other.position = o.position + o.velocity * t;
          other.velocity = o.velocity;
          other.radius = p.radius;
          if (cutoff > 0.0 && (other.position - pos).squaredNorm() > cutoff * cutoff) continue;
          snap.agents.push_back(other);
        }
      }
      const SfmMotion motion =
          manager::modelStep(snap, 0, me, &goal, p.goal_radius, manager::RobotAs::Ignored, speed, Vec2::Zero(), h);
      me.x = motion.position.x();
      me.y = motion.position.y();
      me.vx = motion.velocity.x();
      me.vy = motion.velocity.y();
      me.yaw = motion.yaw;
    }
    out[static_cast<std::size_t>(k)] = Vec2(me.x, me.y);
  }
  return out;
}

Prediction predictWith(const Dataset& d, const Sample& s, const Neighbours& around, const Method& m, const Protocol& p,
                       const GroupIds* groups) {
  return m.constant_velocity ? predictConstantVelocity(s, d.frame_interval) : simulate(d, s, around, m, p, groups);
}

}  // namespace

Prediction predict(const Dataset& d, const Sample& s, const Method& method, const Protocol& p, const GroupIds* groups) {
  return predictWith(d, s, neighboursOf(d, s), method, p, groups);
}

double nearestNeighbour(const Dataset& d, std::int64_t frame, int id, const Vec2& p) {
  const auto f = d.frames.find(frame);
  if (f == d.frames.end()) return -1.0;
  double best = -1.0;
  for (const auto& [other, q] : f->second) {
    if (other == id) continue;
    const double r = (q - p).norm();
    if (best < 0.0 || r < best) best = r;
  }
  return best;
}

double Distribution::mean() const {
  return values.empty() ? std::nan("") : std::accumulate(values.begin(), values.end(), 0.0) / values.size();
}

double Distribution::quantile(double q) const {
  if (values.empty()) return std::nan("");
  const double x = q * (values.size() - 1);
  const std::size_t i = static_cast<std::size_t>(std::floor(x));
  if (i + 1 >= values.size()) return values.back();
  return values[i] + (x - i) * (values[i + 1] - values[i]);
}

double wasserstein1(const Distribution& a, const Distribution& b) {
  if (a.values.empty() || b.values.empty()) return std::nan("");
  // Integral of |F_a^-1(u) - F_b^-1(u)| du over the merged breakpoints of the two step quantile functions.
  const double na = a.values.size(), nb = b.values.size();
  std::size_t i = 0, j = 0;
  double u = 0.0, sum = 0.0;
  while (i < a.values.size() && j < b.values.size()) {
    const double next = std::min((i + 1) / na, (j + 1) / nb);
    sum += (next - u) * std::fabs(a.values[i] - b.values[j]);
    u = next;
    if ((i + 1) / na <= next) ++i;
    if ((j + 1) / nb <= next) ++j;
  }
  return sum;
}

DatasetResult evaluate(const Dataset& d, const std::vector<Method>& methods, const Protocol& p, const GroupIds* groups,
                       ThreadPool* threads, const std::vector<Sample>* only) {
  const auto start = std::chrono::steady_clock::now();
  DatasetResult r;
  r.name = d.name;
  r.path = d.path;
  r.frame_interval = d.frame_interval;
  const std::vector<Sample> all = only == nullptr ? extractSamples(d) : std::vector<Sample>();
  const std::vector<Sample>& samples = only == nullptr ? all : *only;
  r.samples = samples.size();
  r.data.method = "data";
  const std::size_t count = methods.size();
  r.methods.resize(count);
  for (std::size_t m = 0; m < count; ++m) {
    r.methods[m].method = methods[m].name;
    r.methods[m].groups = methods[m].groups;
  }

  // Per sample: the errors and, per method and the data, the 12 speeds, nearest-neighbour distances
  // (< 0: nobody else recorded in that frame) and overlaps, computed in chunks on any thread and
  // added up afterwards in sample order (the same sums with any pool).
  struct Frames {
    std::array<double, kPredicted> speed, nn;
  };
  struct Computed {
    SampleResult result;
    std::vector<Frames> frames;  // [0]: the data, [1 + m]: method m
  };
  std::vector<Computed> computed(samples.size());
  auto measure = [&](const Sample& s, const Prediction& pred, Frames& f) {
    Vec2 prev = s.truth[kObserved - 1];
    for (int k = 0; k < kPredicted; ++k) {
      f.speed[static_cast<std::size_t>(k)] = (pred[static_cast<std::size_t>(k)] - prev).norm() / d.frame_interval;
      prev = pred[static_cast<std::size_t>(k)];
      f.nn[static_cast<std::size_t>(k)] =
          nearestNeighbour(d, s.first_frame + kObserved + k, s.id, pred[static_cast<std::size_t>(k)]);
    }
  };
  auto work = [&](std::size_t i) {
    const Sample& s = samples[i];
    Computed& c = computed[i];
    c.result.id = s.id;
    c.result.first_frame = s.first_frame;
    c.result.ade.resize(count);
    c.result.fde.resize(count);
    c.frames.resize(count + 1);
    Prediction truth;
    std::copy(s.truth.begin() + kObserved, s.truth.end(), truth.begin());
    measure(s, truth, c.frames[0]);
    const Neighbours around = neighboursOf(d, s);
    for (std::size_t m = 0; m < count; ++m) {
      const Prediction pred = predictWith(d, s, around, methods[m], p, groups);
      c.result.ade[m] = ade(pred, s);
      c.result.fde[m] = fde(pred, s);
      measure(s, pred, c.frames[m + 1]);
    }
  };
  constexpr int kChunks = 64;
  const std::size_t n = samples.size();
  auto chunk = [&](int item, int) {
    const std::size_t from = n * static_cast<std::size_t>(item) / kChunks, to = n * (item + 1) / kChunks;
    for (std::size_t i = from; i < to; ++i) work(i);
  };
  if (threads != nullptr)
    threads->run(kChunks, chunk);
  else
    for (int item = 0; item < kChunks; ++item) chunk(item, 0);

  std::vector<std::size_t> overlaps(count + 1, 0), frames(count + 1, 0);
  for (Computed& c : computed) {
    for (std::size_t m = 0; m <= count; ++m) {
      MethodResult& into = m == 0 ? r.data : r.methods[m - 1];
      const Frames& f = c.frames[m];
      for (int k = 0; k < kPredicted; ++k) {
        into.speed.values.push_back(f.speed[static_cast<std::size_t>(k)]);
        const double nn = f.nn[static_cast<std::size_t>(k)];
        if (nn < 0.0) continue;
        into.nn.values.push_back(nn);
        frames[m] += 1;
        if (nn < p.overlap_distance) overlaps[m] += 1;
      }
      if (m > 0) {
        into.ade += c.result.ade[m - 1];
        into.fde += c.result.fde[m - 1];
      }
    }
    c.frames.clear();
    r.per_sample.push_back(std::move(c.result));
  }
  for (std::size_t m = 0; m <= count; ++m) {
    MethodResult& into = m == 0 ? r.data : r.methods[m - 1];
    into.ade = n > 0 ? into.ade / n : std::nan("");
    into.fde = n > 0 ? into.fde / n : std::nan("");
    into.overlaps = frames[m] > 0 ? static_cast<double>(overlaps[m]) / frames[m] : 0.0;
    std::sort(into.speed.values.begin(), into.speed.values.end());
    std::sort(into.nn.values.begin(), into.nn.values.end());
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace hunav::realism
