// The web page's backend (docs/web.md): svetlo's WebAssembly module in a worker of its own
// (render_worker.js), and of it
//   - the `svetlo` object of the contract's "In the browser":
//       await svetlo.ready;
//       const {width, height, seconds, pixels} = await svetlo.render(SCENE, {engine, width,
//           height, spp, seed, threads, set});
//     SCENE is a bundled scene's name ("cornell.json"), a visitor's file put beside them by
//     svetlo.addFiles, or a scene object; pixels is a Float32Array of linear RGB, top row
//     first. A bad scene rejects with an Error whose message is the one-line error. An
//     `onPass(pass)` option is called with each pass of a progressive engine ({passes,
//     seconds, width, height, pixels}); svetlo.cancel() ends the render in progress, which
//     then resolves with `cancelled` true: after its pass with the passes done where the page
//     is cross-origin isolated (within a second, else as elsewhere), elsewhere at once with
//     the last pass onPass was given;
//   - `svetloViewer`, which carries the viewer's requests (the page is svetlo serve's viewer,
//     apps/svetlo/viewer/, whose own backend.js says what it asks): each "/api/..." request
//     answered in the worker by the job layer's ViewerApi, as svetlo serve answers it.
// Requests and renders run one at a time in the worker, in order.
(function () {
    'use strict';
    const script = new URL('render_worker.js', document.currentScript.src);
    const waiting = new Map();  // id -> the call: {resolve, reject, onPass, onChunk, ended}
    let nextId = 1;
    let info = {scenes: [], engines: [], cores: 1, memory: null, cancelAt: 0};
    let worker = null;
    let started = null;  // the current worker's start
    const kept = [];     // the visitor's files, given again to a worker started anew

    /// A worker with the module; resolves once it can take requests. Its messages settle
    /// the calls waiting on it.
    function startWorker() {
        worker = new Worker(script);
        return new Promise((resolve, reject) => {
            worker.onmessage = (event) => {
                const data = event.data;
                if (data.ready) {
                    info = data;
                    resolve();
                    return;
                }
                if (data.failed !== undefined) {
                    reject(new Error('svetlo: the WebAssembly module did not start: ' + data.failed));
                    return;
                }
                const call = waiting.get(data.id);
                if (!call) return;
                if (data.pass !== undefined) {  // a pass of the render in progress
                    call.lastPass = data.pass;
                    if (call.onPass) call.onPass(data.pass);
                    return;
                }
                if (data.chunk !== undefined) {  // bytes of a viewer's stream
                    call.onChunk(data.chunk);
                    return;
                }
                waiting.delete(data.id);
                if (data.response !== undefined) call.resolve(data.response);
                else if (data.error !== undefined) call.reject(new Error(data.error));
                else if (data.names !== undefined) call.resolve(data.names);
                else call.resolve({width: data.width, height: data.height, seconds: data.seconds,
                                   passes: data.passes, cancelled: data.cancelled,
                                   pixels: data.pixels});
            };
            // The worker failed: the start, and every call waiting, end with its message.
            worker.onerror = (event) => {
                const error = new Error('svetlo: ' + event.message);
                reject(error);
                for (const call of waiting.values()) call.reject(error);
                waiting.clear();
            };
        });
    }
    const ready = started = startWorker();

    /// Posts a message to the worker once it has started; `call` waits for its answer. A
    /// worker started anew meanwhile (cancel) gets it once that one has started.
    function post(call, message) {
        const start = started;
        return start.then(() => {
            if (start !== started) return post(call, message);
            return new Promise((resolve, reject) => {
                Object.assign(call, {resolve, reject, message});
                send(nextId++, call);
            });
        });
    }
    function send(id, call) {
        waiting.set(id, call);
        worker.postMessage(Object.assign({id}, call.message));
    }

    /// Threads above one need a cross-origin isolated page (COOP and COEP headers).
    function threadsFor(asked) {
        if (!self.crossOriginIsolated) return 1;
        return asked === undefined || asked === null ? 0 : asked;
    }

    function render(scene, options) {
        const opts = Object.assign({}, options || {});
        const onPass = typeof opts.onPass === 'function' ? opts.onPass : null;
        delete opts.onPass;  // (a function does not cross to the worker)
        opts.threads = threadsFor(opts.threads);
        const isText = typeof scene !== 'string';
        // Ended by a worker's restart (cancel, below): the last pass that came, if onPass
        // asked for them, else an empty image.
        const call = {onPass, ended: () => {
            const p = call.lastPass;
            call.resolve({width: p ? p.width : 0, height: p ? p.height : 0,
                          seconds: p ? p.seconds : 0, passes: p ? p.passes : 0, cancelled: true,
                          pixels: p ? p.pixels : new Float32Array(0)});
        }};
        return post(call, {scene: isText ? JSON.stringify(scene) : scene, isText, options: opts,
                           wantsPasses: onPass !== null});
    }

    /// The visitor's own files (File objects, or {name, bytes} with bytes an ArrayBuffer or a
    /// typed array), put beside the bundled scenes, each under its own name without folders
    /// (one of a bundled scene's name takes its place in this page): a scene or a model and
    /// the files it names (an OBJ's MTL and textures, a glTF's buffers). Resolves to the names
    /// given; svetlo.render('NAME') renders, and the viewer lists it.
    function addFiles(files) {
        return Promise.all(Array.from(files, async (f) => {
            const bytes = f instanceof Blob ? await f.arrayBuffer() : f.bytes;
            const copy = bytes instanceof ArrayBuffer ? bytes.slice(0)
                : bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
            return {name: String(f.name), bytes: copy};
        })).then((list) => {
            const call = {ended: () => call.resolve(list.map((f) => f.name))};
            kept.push(...list);  // (posted as copies: the page keeps its own)
            const answer = post(call, {files: list});
            answer.catch(() => {
                for (const f of list) if (kept.includes(f)) kept.splice(kept.indexOf(f), 1);
            });
            return answer;
        });
    }

    /// How long a render in a cross-origin isolated page has to end after its flag is set,
    /// before its worker is ended as elsewhere: a long setup, or one long pass of the
    /// rasterizer or Whitted, does not read the flag.
    const kCancelGrace = 1000;  // ms

    /// Ends the render in progress. Where the module's memory is shared with the page (a
    /// cross-origin isolated page), it sets the module's flag: the render ends after its pass,
    /// and resolves with the passes done; one still running a second later is ended as
    /// elsewhere. Elsewhere the page cannot reach into the module while it renders: the
    /// worker is ended and a new one started (restart).
    function cancel() {
        const [first] = waiting.keys();  // the worker takes its calls in order
        if (info.memory) {
            Atomics.store(new Int8Array(info.memory), info.cancelAt, 1);
            if (first !== undefined)
                setTimeout(() => { if (waiting.keys().next().value === first) restart(); },
                           kCancelGrace);
            return true;
        }
        if (first !== undefined) restart();
        return true;
    }

    /// Ends the worker and starts a new one, its module loaded again and the visitor's files
    /// given again. The call in progress ends at once: a render resolves with the last pass
    /// that came to onPass (`cancelled` true), a viewer's request rejects as aborted. The
    /// calls after it go to the new worker, in their order.
    function restart() {
        worker.terminate();
        const [[first, call], ...after] = waiting.entries();
        waiting.delete(first);
        started = startWorker().then(() => {
            if (kept.length > 0) worker.postMessage({id: 0, files: kept});
            for (const [id, queued] of after) if (waiting.get(id) === queued) send(id, queued);
        });
        call.ended();
    }

    /// A viewer's request ("/api/render?..."), answered by the worker: {status, type,
    /// headers, body}; for a stream (/api/progressive) its bytes go to onChunk first.
    function request(target, onChunk) {
        const call = {onChunk, ended: () => call.reject(new DOMException('aborted', 'AbortError'))};
        return post(call, onChunk ? {stream: target} : {api: target});
    }

    /// The viewer's fetch: a Response as the browser's fetch would give it from svetlo serve.
    /// The progressive stream's Response comes with its first bytes, its body a stream fed as
    /// the passes come; init.signal's abort ends the render after its pass (svetlo.cancel).
    function viewerFetch(target, init) {
        const url = new URL(target, location.href);
        const path = url.pathname.slice(url.pathname.lastIndexOf('/api/'));
        const signal = init && init.signal;
        const answer = (r) => new Response(r.body,
                                           {status: r.status, headers: Object.assign(
                                               {'Content-Type': r.type}, r.headers)});
        if (!path.startsWith('/api/progressive')) return request(path + url.search).then(answer);
        return new Promise((resolve, reject) => {
            let body = null;
            const stream = new ReadableStream({start(c) { body = c; }});
            let started = false;
            const aborted = () => reject(new DOMException('aborted', 'AbortError'));
            if (signal) {
                if (signal.aborted) return aborted();
                signal.addEventListener('abort', () => {
                    cancel();
                    if (started) body.error(new DOMException('aborted', 'AbortError'));
                    else aborted();
                });
            }
            request(path + url.search, (chunk) => {
                if (!started) {
                    started = true;
                    resolve(new Response(stream, {status: 200}));
                }
                if (!(signal && signal.aborted)) body.enqueue(chunk);
            }).then((r) => {
                if (!started) return resolve(answer(r));
                if (!(signal && signal.aborted)) body.close();
            }, (e) => {
                if (started) body.error(e); else reject(e);
            });
        });
    }

    self.svetloViewer = {
        fetch: viewerFetch,
        ready,
        addFiles,
        get note() {
            return self.crossOriginIsolated
                ? `rendered in this page, on ${info.cores} threads`
                : 'rendered in this page on one thread: it is not cross-origin isolated (docs/web.md)';
        },
    };

    self.svetlo = {
        ready,
        render,
        addFiles,
        cancel,
        canCancel: true,
        get scenes() { return info.scenes.slice(); },
        get engines() { return info.engines.map((e) => e.name); },
        get threads() { return self.crossOriginIsolated ? info.cores : 1; },
    };
})();
