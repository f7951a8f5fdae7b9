// Stand-in for the Arduino-ESP32 WiFi library: the calls esp32-mqtt.ino makes (see Arduino.h
// here).
#ifndef TWINLINK_TEST_WIFI_H
#define TWINLINK_TEST_WIFI_H

#include "Arduino.h"

typedef enum {
  WL_IDLE_STATUS = 0,
  WL_NO_SSID_AVAIL = 1,
  WL_SCAN_COMPLETED = 2,
  WL_CONNECTED = 3,
  WL_CONNECT_FAILED = 4,
  WL_CONNECTION_LOST = 5,
  WL_DISCONNECTED = 6,
} wl_status_t;

typedef enum { WIFI_OFF = 0, WIFI_STA = 1, WIFI_AP = 2, WIFI_AP_STA = 3 } wifi_mode_t;

class Client {
 public:
  virtual ~Client() {}
};

class WiFiClient : public Client {};

class WiFiClass {
 public:
  bool mode(wifi_mode_t mode);
  wl_status_t begin(const char* ssid, const char* passphrase = nullptr);
  wl_status_t status();
};

extern WiFiClass WiFi;

#endif  // TWINLINK_TEST_WIFI_H
