// The messages of twinlink_mqtt as the platform sees them: tests/integration/test_esp32_example.py
// reads what this program writes with the platform's own parsers, and gives it what the
// platform sends, so the example cannot drift from the scheme.
//
//   wire_check emit PREFIX TWIN DEVICE    one line per message: kind TAB topic TAB payload
//   wire_check parse PREFIX TWIN DEVICE   reads lines: kind TAB topic TAB payload-in-hex
//                                         (kind command or desired), writes one JSON line each
//   wire_check names                      reads lines: kind TAB name-in-hex (twin, device,
//                                         command_id, stream), writes 1 or 0: whether valid
#include <stdio.h>
#include <string.h>

#include <iostream>
#include <string>
#include <vector>

#include "twinlink_mqtt.h"

using twinlink::Device;
using twinlink::Field;
using twinlink::JsonWriter;
using twinlink::Value;

namespace {

const char kCommandId[] = "pX3k9Qw2ZbT7cV1a";

void line(const char* kind, const char* topic, const char* payload) {
  printf("%s\t%s\t%s\n", kind, topic, payload);
}

bool emit(const Device& device) {
  char topic[256];
  char payload[1024];
  bool ok = true;

  const Field sample[] = {
      {"Cantilever_Angle_radians", Value::of_number(0.123)},
      {"Input_F_in", Value::of_number(1.1931)},
  };
  ok &= twinlink::telemetry_topic(topic, sizeof topic, device, nullptr);
  ok &= twinlink::format_telemetry(payload, sizeof payload, sample, 2);
  line("telemetry", topic, payload);

  const Field mixed[] = {
      {"flag", Value::of_bool(true)},
      {"label", Value::of_text("say \"hi\" \xc3\xa4\n")},
      {"tiny", Value::of_number(1e-300)},
  };
  ok &= twinlink::format_telemetry(payload, sizeof payload, mixed, 3);
  line("telemetry-mixed", topic, payload);

  twinlink::TelemetryBatch batch(payload, sizeof payload);
  for (int i = 0; i < 3; ++i) {
    const Field values[] = {
        {"Cantilever_Angle_radians", Value::of_number(0.1 * i)},
        {"Input_F_in", Value::of_number(0.97 * i)},
    };
    ok &= batch.add(1732200000123ULL + 10 * i, values, 2);
  }
  line("telemetry-batch", topic, batch.payload());
  batch.clear();
  ok &= batch.add(0, sample, 2);
  line("telemetry-untimed", topic, batch.payload());
  ok &= twinlink::telemetry_topic(topic, sizeof topic, device, "esp32");
  ok &= twinlink::format_telemetry(payload, sizeof payload, sample, 2);
  line("telemetry-stream", topic, payload);

  ok &= twinlink::command_topic(topic, sizeof topic, device, kCommandId, twinlink::kDelivered);
  ok &= twinlink::format_delivered(payload, sizeof payload);
  line("delivered", topic, payload);

  ok &= twinlink::command_topic(topic, sizeof topic, device, kCommandId, twinlink::kResult);
  const Field result[] = {{"sample_rate", Value::of_number(50)}};
  ok &= twinlink::format_result_succeeded(payload, sizeof payload, result, 1);
  line("succeeded", topic, payload);
  ok &= twinlink::format_result_succeeded(payload, sizeof payload, nullptr, 0);
  line("succeeded-empty", topic, payload);
  ok &= twinlink::format_result_failed(payload, sizeof payload, "value \"500\" is not 1..100\n");
  line("failed", topic, payload);

  ok &= twinlink::device_topic(topic, sizeof topic, device, twinlink::kReported);
  const Field reported[] = {
      {"sample_rate", Value::of_number(20)},
      {"paused", Value::of_bool(false)},
      {"device_id", Value::of_text(device.name)},
  };
  ok &= twinlink::format_reported(payload, sizeof payload, reported, 3);
  line("reported", topic, payload);

  ok &= twinlink::device_topic(topic, sizeof topic, device, twinlink::kStatus);
  line("status", topic, "online");

  const char* filters[] = {twinlink::kCommandFilter, twinlink::kDesired, twinlink::kErrors,
                           twinlink::kAcks};
  for (const char* leaf : filters) {
    ok &= twinlink::device_topic(topic, sizeof topic, device, leaf);
    line("subscribe", topic, "");
  }
  return ok;
}

std::string from_hex(const std::string& hex) {
  std::string bytes;
  for (size_t i = 0; i + 1 < hex.size(); i += 2) {
    bytes += static_cast<char>(std::stoi(hex.substr(i, 2), nullptr, 16));
  }
  return bytes;
}

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> parts;
  size_t start = 0;
  for (;;) {
    size_t tab = text.find('\t', start);
    parts.push_back(text.substr(start, tab - start));
    if (tab == std::string::npos) return parts;
    start = tab + 1;
  }
}

// Text the platform's side compares byte for byte goes back as hex: it may be anything.
std::string to_hex(const char* text) {
  static const char digits[] = "0123456789abcdef";
  std::string hex;
  for (const unsigned char* s = reinterpret_cast<const unsigned char*>(text); *s; ++s) {
    hex += digits[*s >> 4];
    hex += digits[*s & 15];
  }
  return hex;
}

void parse_one(const Device& device, const std::vector<std::string>& parts) {
  std::string payload = from_hex(parts[2]);
  std::vector<char> exact(payload.begin(), payload.end());  // no NUL after it
  char out[512];
  JsonWriter json(out, sizeof out);
  json.open_object();
  if (parts[0] == "desired") {
    double value = 0;
    bool read = twinlink::parse_desired_number(exact.data(), exact.size(), "sample_rate", &value);
    json.key("ok").boolean(read);
    if (read) json.key("value").number(value);
  } else {
    twinlink::Command command;
    bool read = twinlink::parse_command(parts[1].c_str(), exact.data(), exact.size(), device,
                                        &command);
    json.key("ok").boolean(read).key("id").text(command.id);
    if (read) {
      json.key("name_hex").text(to_hex(command.name).c_str());
      if (command.has_value) json.key("value").number(command.value);
    } else {
      json.key("error").text(command.error);
    }
  }
  json.close_object();
  puts(json.ok() ? out : "{\"ok\":null}");
}

bool validate(const std::string& kind, const std::string& name) {
  if (kind == "twin") return twinlink::valid_twin(name.c_str());
  if (kind == "stream") return twinlink::valid_stream(name.c_str());
  if (kind == "device") return twinlink::valid_device_name(name.c_str());
  return twinlink::valid_command_id(name.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  std::string mode = argc > 1 ? argv[1] : "";
  if (mode == "names") {
    std::string text;
    while (std::getline(std::cin, text)) {
      std::vector<std::string> parts = split(text);
      std::string name = from_hex(parts.size() > 1 ? parts[1] : "");
      bool whole = name.find('\0') == std::string::npos;
      puts(whole && validate(parts[0], name) ? "1" : "0");
    }
    return 0;
  }
  if (argc != 5 || (mode != "emit" && mode != "parse")) {
    fprintf(stderr, "usage: wire_check emit|parse PREFIX TWIN DEVICE, or wire_check names\n");
    return 2;
  }
  Device device = {argv[2], argv[3], argv[4]};
  if (mode == "emit") return emit(device) ? 0 : 1;
  std::string text;
  while (std::getline(std::cin, text)) {
    std::vector<std::string> parts = split(text);
    if (parts.size() != 3) {
      fprintf(stderr, "expected kind TAB topic TAB hex: %s\n", text.c_str());
      return 2;
    }
    parse_one(device, parts);
    fflush(stdout);
  }
  return 0;
}
