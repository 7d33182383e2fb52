"""Virtual on-board sensors: what accelerometers, gyros, air-spring sensors and an odometer on the car would
record of a run (instruments: the sensor models; config: the sensor set; measure: the signals). docs/onboard.md."""
