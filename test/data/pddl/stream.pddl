(define (stream toy))
