import { execFileSync, spawnSync } from 'node:child_process'
import { describe, expect, it } from 'vitest'
import { defaultConfig, helpText, loadConfig, SETTINGS } from '../../../server/config/config.ts'

describe('server configuration', () => {
  it('flags beat environment variables, which beat defaults', () => {
    expect(loadConfig([], {}).port).toBe(8080)
    expect(loadConfig([], { PORT: '9000' }).port).toBe(9000)
    expect(loadConfig(['--port', '9100'], { PORT: '9000' }).port).toBe(9100)
    expect(loadConfig(['--port=9200'], {}).port).toBe(9200)
    expect(loadConfig(['--room-controls', 'false'], {}).roomControls).toBe(false)
    expect(loadConfig(['--room-controls'], {}).roomControls).toBe(true)
    expect(loadConfig([], { HOST: '0.0.0.0', SNAPSHOT_RATE: '60' })).toMatchObject({
      host: '0.0.0.0',
      snapshotRate: 60,
    })
  })

  it('every setting has a flag, an environment variable and a default', () => {
    const defaults = defaultConfig() as unknown as Record<string, unknown>
    for (const s of SETTINGS) {
      expect(s.flag).toMatch(/^--[a-z-]+$/)
      expect(s.env).toMatch(/^[A-Z_]+$/)
      expect(defaults[s.key]).toBe(s.fallback)
    }
  })

  const bad: Array<[string, string[], Record<string, string>]> = [
    ['a non-numeric port', ['--port', 'http'], {}],
    ['a port out of range', [], { PORT: '70000' }],
    ['a snapshot rate that does not divide 60', ['--snapshot-rate', '7'], {}],
    ['an unknown flag', ['--prot', '1'], {}],
    ['a flag without a value', ['--port'], {}],
    ['an unknown scene', ['--default-scene', 'nope'], {}],
    ['a bad room name', [], { DEFAULT_ROOM: '../x' }],
    ['an unknown log level', ['--log-level', 'loud'], {}],
    ['a non-boolean', ['--room-controls', 'maybe'], {}],
    ['an unknown fsync mode', ['--replay-fsync', 'sometimes'], {}],
    ['a keyframe interval below a second', [], { KEYFRAME_TICKS: '10' }],
    ['a non-boolean record flag', [], { RECORD: 'perhaps' }],
  ]
  for (const [what, argv, env] of bad) {
    it(`refuses ${what} with a message naming the setting`, () => {
      expect(() => loadConfig(argv, env)).toThrow(
        /port|snapshot|unknown option|needs a value|scene|room|log level|room-controls|replay fsync|KEYFRAME_TICKS|RECORD must/i,
      )
    })
  }
})

describe('--help', () => {
  it('lines every column up under its header, however long a flag or env name is', () => {
    const lines = helpText().split('\n')
    const header = lines.find((l) => l.trimStart().startsWith('flag'))!
    const at = {
      env: header.indexOf('env'),
      fallback: header.indexOf('default'),
      meaning: header.indexOf('meaning'),
    }
    const rows = lines.filter((l) => /^ {2}--/.test(l))
    expect(rows).toHaveLength(SETTINGS.length)
    for (const [i, row] of rows.entries()) {
      const s = SETTINGS[i]
      // The oracle is the setting itself: its env name starts at the env column, its meaning at
      // the meaning column, each after at least two spaces.
      expect(row.slice(at.env - 2, at.env + s.env.length), row).toBe(`  ${s.env}`)
      expect(row.slice(at.meaning - 2), row).toBe(`  ${s.help}`)
      expect(row.slice(at.fallback - 2, at.fallback), row).toBe('  ')
    }
  })
})

describe('--workers', () => {
  it('defaults to one worker per core, and --help says so', () => {
    // The oracle: the cores Node may use here (nproc), counted independently of server/config/config.ts.
    const cores = Number(execFileSync('nproc', { encoding: 'utf8', env: { PATH: process.env.PATH } }).trim())
    expect(cores).toBeGreaterThan(0)
    expect(loadConfig([], {}).workers).toBe(cores)
    expect(loadConfig([], { WORKERS: '' }).workers).toBe(cores)
    const row = helpText()
      .split('\n')
      .find((l) => l.trimStart().startsWith('--workers'))
    expect(row).toContain('one per core')
    expect(row).toContain('0 = every room on the main thread')
  })

  it('takes a worker count from 0 (rooms on the main thread) to 256, and refuses anything else naming the setting', () => {
    expect(loadConfig(['--workers', '0'], {}).workers).toBe(0)
    expect(loadConfig([], { WORKERS: '0' }).workers).toBe(0)
    expect(loadConfig(['--workers', '3'], {}).workers).toBe(3)
    expect(loadConfig([], { WORKERS: '2' }).workers).toBe(2)
    expect(() => loadConfig(['--workers', '-1'], {})).toThrow(
      '--workers must be an integer in [0, 256], got "-1"',
    )
    expect(() => loadConfig([], { WORKERS: '1.5' })).toThrow(
      'WORKERS must be an integer in [0, 256], got "1.5"',
    )
    expect(() => loadConfig(['--workers', '257'], {})).toThrow(/--workers/)
    expect(() => loadConfig(['--workers', 'all'], {})).toThrow(/--workers/)
  })
})

describe('the README settings table', () => {
  it('lists every setting with its flag, environment variable and default', async () => {
    const { readFileSync } = await import('node:fs')
    const rows = readFileSync('README.md', 'utf8')
      .split('\n')
      .filter((l) => l.startsWith('| `--'))
    for (const s of SETTINGS) {
      const row = rows.find((r) => r.startsWith(`| \`${s.flag}\``))
      expect(row, `README row for ${s.flag}`).toBeDefined()
      expect(row).toContain(`\`${s.env}\``)
      const cells = row!.split('|').map((c) => c.trim())
      const documented = cells[3]
      if (s.shown) expect(documented, `README default of ${s.flag}`).toBe(s.shown)
      else
        expect(s.fallback === '' ? documented.startsWith('(') : documented === String(s.fallback)).toBe(true)
    }
  })
})

describe('a bad --host', () => {
  /** `server/main.ts` (the real command line) with `--host host`; its exit code and standard error. */
  const start = (host: string): { status: number | null; stderr: string } => {
    const args = [
      '--port',
      '0',
      '--host',
      host,
      '--workers',
      '0',
      '--record',
      'false',
      '--log-level',
      'silent',
    ]
    const r = spawnSync(process.execPath, ['--import', 'tsx', 'server/main.ts', ...args], {
      encoding: 'utf8',
      timeout: 20_000,
    })
    return { status: r.status, stderr: r.stderr }
  }

  it('that is no address or host name stops startup with one line naming the setting and value, no stack', () => {
    for (const host of ['', 'not a host', '[::1]', 'http://127.0.0.1']) {
      const r = start(host)
      expect(r.status, host).toBe(2)
      expect(r.stderr, host).toBe(
        `concord: host (--host, HOST) must be an IP address or a host name, got "${host}"\n`,
      )
    }
    expect(loadConfig([], { HOST: '::1' }).host).toBe('::1')
    expect(loadConfig(['--host', 'fe80::1%lo'], {}).host).toBe('fe80::1%lo')
    expect(loadConfig(['--host', 'game-1.example.com'], {}).host).toBe('game-1.example.com')
  })

  it('that cannot be listened on (not an address of this machine) stops startup with one line, no stack', {
    timeout: 30_000,
  }, () => {
    // 192.0.2.1 is TEST-NET-1 (RFC 5737): never an address of this machine, no DNS involved.
    const r = start('192.0.2.1')
    expect(r.status).toBe(1)
    expect(r.stderr).toMatch(
      /^concord: cannot listen on --host 192\.0\.2\.1 --port 0: listen EADDRNOTAVAIL[^\n]*\n$/,
    )
  })

  it('refuses a --replay-max-bytes below 4 MiB, saying why (a log must hold more than its header)', () => {
    expect(loadConfig(['--replay-max-bytes', String(4 * 1024 * 1024)], {}).replayMaxBytes).toBe(4_194_304)
    // 65,536 was accepted: below the 113 KB header of an awake pyramid, every tick rotated.
    expect(() => loadConfig(['--replay-max-bytes', '65536'], {})).toThrow(
      '--replay-max-bytes must be an integer of at least 4194304, got "65536": a new log starts with a header holding the whole saved world',
    )
    expect(() => loadConfig([], { REPLAY_MAX_BYTES: '4194303' })).toThrow(
      /^REPLAY_MAX_BYTES must be .* at least 4194304/,
    )
  })
})
