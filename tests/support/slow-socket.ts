/*
 * A real client socket under a test's control: the TCP socket under a `ws` client, and a reader
 * that takes one chunk at a time with pauses between (a client that reads, but slowly).
 */
import type { Socket } from 'node:net'

/** The TCP socket under a `ws` WebSocket (its private `_socket`). */
export function socketOf(ws: unknown): Socket {
  return (ws as { _socket: Socket })._socket
}

/**
 * Reads one chunk (at most 64 KiB) at once, then one every `everyMs`, paused between. The first
 * read is not left to the interval: on a quiet machine the server's slow-reader rule (1 s over
 * the budget in the tests) can close the reader before a first interval has passed.
 */
export function readSlowly(ws: unknown, everyMs: number): { chunks: () => number; stop: () => void } {
  const socket = socketOf(ws)
  socket.pause()
  let chunks = 0
  const readOneChunk = () => {
    socket.once('data', () => {
      chunks++
      socket.pause()
    })
    socket.resume()
  }
  readOneChunk()
  const timer = setInterval(readOneChunk, everyMs)
  return { chunks: () => chunks, stop: () => clearInterval(timer) }
}
