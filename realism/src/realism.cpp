#include "hunav/realism/realism.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "hunav/config_error.hpp"
#include "hunav/manager/agent_manager.hpp"
#include "hunav/social_force.hpp"
#include "hunav/yaml_reader.hpp"

namespace hunav::realism {

ModelParams readParams(const std::string& path, const ModelParams& base) {
  const YamlReader yaml(path);
  const YAML::Node& root = yaml.root();
  if (!root.IsMap()) yaml.fail(root, "", "expected a mapping of parameters");
  ModelParams p = base;
  struct Key {
    const char* name;
    double* value;
    bool positive;  // must be > 0 (else >= 0, or anything for desired_speed / cutoff)
    bool any_sign;
  };
  const Key keys[] = {{"goal_weight", &p.goal_weight, false, false},
                      {"obstacle_weight", &p.obstacle_weight, false, false},
                      {"social_weight", &p.social_weight, false, false},
                      {"desired_speed", &p.desired_speed, false, true},
                      {"radius", &p.radius, false, false},
                      {"goal_radius", &p.goal_radius, false, false},
                      {"dt", &p.dt, true, false},
                      {"cutoff", &p.cutoff, false, true},
                      {"goal_distance", &p.goal_distance, true, false}};
  for (const auto& kv : root) {
    const std::string name = kv.first.as<std::string>();
    const Key* key = nullptr;
    for (const Key& k : keys)
      if (name == k.name) key = &k;
    if (key == nullptr)
      yaml.fail(kv.first, name,
                "unknown parameter (known: goal_weight, obstacle_weight, social_weight, desired_speed, radius, "
                "goal_radius, dt, cutoff, goal_distance)");
    const double v = yaml.convert<double>(kv.second, name);
    if (key->positive && !(v > 0.0)) yaml.fail(kv.second, name, "expected a number > 0");
    if (!key->positive && !key->any_sign && v < 0.0) yaml.fail(kv.second, name, "expected a number >= 0");
    if (name == "desired_speed" && v > kMaxSpeed) yaml.fail(kv.second, name, "expected at most 10 m/s");
    *key->value = v;
  }
  return p;
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

double desiredSpeedOf(const Sample& s, double interval, const ModelParams& p) {
  if (p.desired_speed >= 0.0) return p.desired_speed;
  double path = 0.0;
  for (int k = 1; k < kObserved; ++k) path += (s.truth[k] - s.truth[k - 1]).norm();
  return std::min(path / ((kObserved - 1) * interval), kMaxSpeed);
}

Vec2 goalOf(const Sample& s, double interval, const ModelParams& p, GoalMode mode) {
  if (mode == GoalMode::Oracle) return s.truth.back();
  const Vec2 velocity = (s.truth[kObserved - 1] - s.truth[kObserved - 2]) / interval;
  return s.truth[kObserved - 1] + velocity * (p.goal_distance * kPredicted * interval);
}

Prediction predictSocialForce(const Dataset& d, const Sample& s, const ModelParams& p, GoalMode mode) {
  const double interval = d.frame_interval;
  // The focal person as the manager sees it: a regular person with the weights being scored and no
  // obstacle points (the data sets come without maps).
  agent_state_t me{};
  me.id = s.id;
  me.type = agent_state_t::TYPE_PERSON;
  me.behavior = agent_state_t::BEH_REGULAR;
  me.group_id = -1;
  me.radius = p.radius;
  me.goal_radius = p.goal_radius;
  me.behavior_params.goal_force_factor = p.goal_weight;
  me.behavior_params.obstacle_force_factor = p.obstacle_weight;
  me.behavior_params.social_force_factor = p.social_weight;
  const double speed = desiredSpeedOf(s, interval, p);
  me.desired_speed = speed;
  const Vec2 goal = goalOf(s, interval, p, mode);

  Vec2 pos = s.truth[kObserved - 1];
  Vec2 vel = (s.truth[kObserved - 1] - s.truth[kObserved - 2]) / interval;
  double yaw = vel.squaredNorm() > 0.0 ? angleOf(vel) : 0.0;
  // A frame interval split into n equal steps no longer than dt (0.4 s / 0.01 s = 40 steps exactly).
  const int n = std::max(1, static_cast<int>(std::ceil(interval / p.dt - 1e-9)));
  const double h = interval / n;

  manager::StepSnapshot snap;
  Prediction out;
  for (int k = 0; k < kPredicted; ++k) {
    const std::int64_t f0 = s.first_frame + kObserved - 1 + k;
    const auto& a = d.frames.at(f0);
    const auto& b = d.frames.at(f0 + 1);
    // The neighbours of this interval: recorded at both of its frames.
    std::vector<std::pair<Vec2, Vec2>> others;  // position at f0, velocity over the interval
    for (const auto& [id, pa] : a) {
      if (id == s.id) continue;
      const auto pb = b.find(id);
      if (pb != b.end()) others.emplace_back(pa, (pb->second - pa) / interval);
    }
    for (int i = 0; i < n; ++i) {
      const double t = i * h;
      snap.agents.clear();
      SfmBody body;
      body.id = s.id;
      body.position = pos;
      body.velocity = vel;
      body.radius = p.radius;
      snap.agents.push_back(body);
      for (std::size_t j = 0; j < others.size(); ++j) {
        SfmBody o;
        o.id = -1 - static_cast<int>(j);  // ids only have to differ from the focal person's
        o.position = others[j].first + others[j].second * t;
        o.velocity = others[j].second;
        o.radius = p.radius;
        if (p.cutoff > 0.0 && (o.position - pos).squaredNorm() > p.cutoff * p.cutoff) continue;
        snap.agents.push_back(o);
      }
      const ForceSet f = manager::computeForces(snap, 0, me, &goal, manager::RobotAs::Ignored, speed);
      const SfmMotion m = integrate(pos, vel, yaw, f.total, speed, h);
      pos = m.position;
      vel = m.velocity;
      yaw = m.yaw;
    }
    out[k] = pos;
  }
  return out;
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

DatasetResult evaluate(const Dataset& d, const ModelParams& p) {
  const auto start = std::chrono::steady_clock::now();
  DatasetResult r;
  r.name = d.name;
  r.path = d.path;
  r.frame_interval = d.frame_interval;
  const std::vector<Sample> samples = extractSamples(d);
  r.samples = samples.size();
  r.data.method = "data";
  r.methods.resize(kMethods);
  for (int m = 0; m < kMethods; ++m) r.methods[m].method = kMethodNames[m];

  auto collect = [&](MethodResult& into, const Sample& s, const Prediction& pred) {
    Vec2 prev = s.truth[kObserved - 1];
    for (int k = 0; k < kPredicted; ++k) {
      into.speed.values.push_back((pred[k] - prev).norm() / d.frame_interval);
      prev = pred[k];
      const double nn = nearestNeighbour(d, s.first_frame + kObserved + k, s.id, pred[k]);
      if (nn >= 0.0) into.nn.values.push_back(nn);
    }
  };
  for (const Sample& s : samples) {
    SampleResult sr;
    sr.id = s.id;
    sr.first_frame = s.first_frame;
    Prediction truth;
    std::copy(s.truth.begin() + kObserved, s.truth.end(), truth.begin());
    collect(r.data, s, truth);
    const Prediction preds[kMethods] = {predictConstantVelocity(s, d.frame_interval),
                                        predictSocialForce(d, s, p, GoalMode::Extrapolated),
                                        predictSocialForce(d, s, p, GoalMode::Oracle)};
    for (int m = 0; m < kMethods; ++m) {
      sr.ade[m] = ade(preds[m], s);
      sr.fde[m] = fde(preds[m], s);
      r.methods[m].ade += sr.ade[m];
      r.methods[m].fde += sr.fde[m];
      collect(r.methods[m], s, preds[m]);
    }
    r.per_sample.push_back(sr);
  }
  for (MethodResult* m : {&r.data, &r.methods[0], &r.methods[1], &r.methods[2]}) {
    if (!samples.empty()) {
      m->ade /= samples.size();
      m->fde /= samples.size();
    }
    std::sort(m->speed.values.begin(), m->speed.values.end());
    std::sort(m->nn.values.begin(), m->nn.values.end());
  }
  if (samples.empty())
    for (MethodResult& m : r.methods) m.ade = m.fde = std::nan("");
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace hunav::realism
