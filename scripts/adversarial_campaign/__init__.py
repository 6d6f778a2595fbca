"""The adversarial campaign against the sonarsynth CLI (docs/adversarial-testing.md); run it with
scripts/adversarial.py."""
