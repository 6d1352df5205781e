/*
 * A client SDK session that records the events of its connection's life (reconnecting,
 * reconnected, close, error) in order, for the SDK's reconnect and moved tests. `connect` is the
 * SDK's: the built bundle's (sdk-reconnect.test.ts) or the source's (sdk-moved.test.ts).
 */
import WebSocket from 'ws'
import type { ConnectOptions, Session, SessionEvents } from '../../sdk/index.ts'

export interface RecordingSession {
  session: Session
  log: Array<{ type: keyof SessionEvents; value: unknown }>
  /** The values of every event of `type`, in order. */
  of<K extends keyof SessionEvents>(type: K): SessionEvents[K][]
}

/** Connects (name 'r', the `ws` package's WebSocket, then `extra`) and records the session's events. */
export async function recordingSession(
  connect: (options: ConnectOptions) => Promise<Session>,
  url: string,
  room: string,
  extra: Partial<ConnectOptions> = {},
): Promise<RecordingSession> {
  const log: RecordingSession['log'] = []
  const record = (type: keyof SessionEvents) => (value: unknown) => log.push({ type, value })
  const session = await connect({
    url,
    room,
    name: 'r',
    WebSocket: WebSocket as unknown as ConnectOptions['WebSocket'],
    on: {
      reconnecting: record('reconnecting'),
      reconnected: record('reconnected'),
      close: record('close'),
      error: record('error'),
    },
    ...extra,
  })
  const of = <K extends keyof SessionEvents>(type: K) =>
    log.filter((e) => e.type === type).map((e) => e.value as SessionEvents[K])
  return { session, log, of }
}
