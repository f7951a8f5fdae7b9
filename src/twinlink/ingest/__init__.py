"""Device-facing ingest: batches from devices become durable samples on the bus."""
