// Stand-in for PubSubClient 2.8 (knolleary/pubsubclient, src/PubSubClient.h): the calls
// esp32-mqtt.ino makes, with the library's signatures (see Arduino.h here).
#ifndef TWINLINK_TEST_PUBSUBCLIENT_H
#define TWINLINK_TEST_PUBSUBCLIENT_H

#include <functional>

#include "Arduino.h"
#include "WiFi.h"

typedef bool boolean;

#define MQTT_CONNECTION_TIMEOUT -4
#define MQTT_CONNECTION_LOST -3
#define MQTT_CONNECT_FAILED -2
#define MQTT_DISCONNECTED -1
#define MQTT_CONNECTED 0
#define MQTT_CONNECT_BAD_PROTOCOL 1
#define MQTT_CONNECT_BAD_CLIENT_ID 2
#define MQTT_CONNECT_UNAVAILABLE 3
#define MQTT_CONNECT_BAD_CREDENTIALS 4
#define MQTT_CONNECT_UNAUTHORIZED 5

// On the ESP32 the callback is a std::function.
#define MQTT_CALLBACK_SIGNATURE std::function<void(char*, uint8_t*, unsigned int)> callback

class PubSubClient {
 public:
  explicit PubSubClient(Client& client);
  PubSubClient& setServer(const char* domain, uint16_t port);
  PubSubClient& setCallback(MQTT_CALLBACK_SIGNATURE);
  PubSubClient& setKeepAlive(uint16_t keepAlive);
  PubSubClient& setSocketTimeout(uint16_t timeout);
  boolean setBufferSize(uint16_t size);
  boolean connect(const char* id, const char* user, const char* pass, const char* willTopic,
                  uint8_t willQos, boolean willRetain, const char* willMessage);
  boolean publish(const char* topic, const uint8_t* payload, unsigned int plength,
                  boolean retained);
  boolean subscribe(const char* topic, uint8_t qos);
  boolean loop();
  boolean connected();
  int state();
};

#endif  // TWINLINK_TEST_PUBSUBCLIENT_H
