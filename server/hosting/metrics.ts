/*
 * Prometheus metrics for one server instance, on a registry of its own (so several servers in one
 * test process do not collide). Served at /metrics.
 */
import { Counter, collectDefaultMetrics, Gauge, Histogram, Registry } from 'prom-client'

/** The server's metrics. */
export interface ServerMetrics {
  registry: Registry
  rooms: Gauge
  clients: Gauge
  connections: Gauge
  tickSeconds: Histogram
  loopTickSeconds: Histogram<'loop'>
  roomDroppedTicks: Counter<'room'>
  bytesSent: Counter
  bytesReceived: Counter
  roomsClosedOverBudget: Counter
  messagesReceived: Counter
  rejected: Counter<'reason'>
  overruns: Counter
  snapshotsSkipped: Counter
  slowClientsClosed: Counter
  desyncs: Counter
  connectionsRefused: Counter<'reason'>
  recorderFailures: Counter
  roomsRecovered: Counter
  workersFailed: Counter
  roomsRefused: Counter<'reason'>
  roomsUntouchedClosed: Counter
}

/** Create the metrics on a fresh registry; `processMetrics` adds Node's default process metrics. */
export function createMetrics(processMetrics: boolean): ServerMetrics {
  const registry = new Registry()
  if (processMetrics) collectDefaultMetrics({ register: registry })
  const registers = [registry]
  return {
    registry,
    rooms: new Gauge({ name: 'concord_rooms', help: 'Open rooms', registers }),
    clients: new Gauge({ name: 'concord_clients', help: 'Joined players', registers }),
    connections: new Gauge({ name: 'concord_connections', help: 'Open WebSocket connections', registers }),
    tickSeconds: new Histogram({
      name: 'concord_room_tick_seconds',
      help: 'Time to run one room tick: inputs, step, snapshots',
      buckets: [0.0001, 0.00025, 0.0005, 0.001, 0.002, 0.004, 0.008, 0.016, 0.032],
      registers,
    }),
    loopTickSeconds: new Histogram({
      name: 'concord_loop_tick_seconds',
      help: 'Time for one tick of every room on a tick loop (loop="main" for the in-process clock)',
      labelNames: ['loop'],
      buckets: [0.0005, 0.001, 0.002, 0.004, 0.008, 0.012, 0.0167, 0.025, 0.05, 0.1],
      registers,
    }),
    roomDroppedTicks: new Counter({
      name: 'concord_room_dropped_ticks_total',
      help: 'Ticks a room skipped because its tick loop fell behind, by room (open rooms only)',
      labelNames: ['room'],
      registers,
    }),
    roomsClosedOverBudget: new Counter({
      name: 'concord_rooms_closed_over_budget_total',
      help: 'Rooms closed for exceeding the per-room tick budget repeatedly',
      registers,
    }),
    bytesReceived: new Counter({
      name: 'concord_bytes_received_total',
      help: 'WebSocket payload bytes received from clients (before any check)',
      registers,
    }),
    bytesSent: new Counter({
      name: 'concord_bytes_sent_total',
      help: 'WebSocket payload bytes sent',
      registers,
    }),
    messagesReceived: new Counter({
      name: 'concord_messages_received_total',
      help: 'Client messages received',
      registers,
    }),
    rejected: new Counter({
      name: 'concord_messages_rejected_total',
      help: 'Client messages rejected, by reason',
      labelNames: ['reason'],
      registers,
    }),
    overruns: new Counter({
      name: 'concord_tick_overruns_total',
      help: 'Ticks dropped because the loop fell behind',
      registers,
    }),
    snapshotsSkipped: new Counter({
      name: 'concord_snapshots_skipped_total',
      help: 'Snapshots skipped for full send buffers',
      registers,
    }),
    slowClientsClosed: new Counter({
      name: 'concord_slow_clients_closed_total',
      help: 'Clients closed for not reading',
      registers,
    }),
    desyncs: new Counter({
      name: 'concord_desyncs_total',
      help: 'State hash mismatches reported (lockstep mode)',
      registers,
    }),
    connectionsRefused: new Counter({
      name: 'concord_connections_refused_total',
      help: 'TCP connections, requests and upgrades refused, by reason (caps, request rate, origin, token)',
      labelNames: ['reason'],
      registers,
    }),
    recorderFailures: new Counter({
      name: 'concord_recorder_failures_total',
      help: 'Room recordings stopped by a write error (the rooms kept running)',
      registers,
    }),
    roomsRecovered: new Counter({
      name: 'concord_rooms_recovered_total',
      help: 'Rooms reopened from their logs after a crash',
      registers,
    }),
    roomsRefused: new Counter({
      name: 'concord_rooms_refused_total',
      help: 'Joins refused because they would open a room, by reason (rate: the address opened --max-new-rooms-per-ip this minute)',
      labelNames: ['reason'],
      registers,
    }),
    roomsUntouchedClosed: new Counter({
      name: 'concord_rooms_untouched_closed_total',
      help: 'Rooms closed as soon as they were empty because no command was ever applied in them (their logs removed)',
      registers,
    }),
    workersFailed: new Counter({
      name: 'concord_room_workers_failed_total',
      help: 'Room worker threads that died (their clients were closed with 4008, their rooms rebuilt from logs when recording)',
      registers,
    }),
  }
}
